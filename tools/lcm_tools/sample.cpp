#include "sample.hpp"

#include <map>
#include <set>

#include "runtime/channels.hpp"

namespace hg::lcmtools {

namespace {

struct Filler {
  const Schema& schema;
  int64_t seq;
  int64_t utime;
  int64_t k = 0;  // running index of the value in the message

  Json element(const Member& m, const std::string& name) {
    int64_t x = seq * 1000 + k++;
    switch (m.kind) {
      case Kind::Int8: return (seq + k) % 128;
      case Kind::Int16: return (seq * 100 + k) % 32768;
      case Kind::Int32: return x % 2147483647;
      case Kind::Int64: return x;
      case Kind::Byte: return (seq + k) % 256;
      case Kind::Boolean: return (seq + k) % 2 == 1;
      case Kind::Float: return static_cast<double>(seq % 4096) + static_cast<double>(k % 64) / 8.0;  // exact in float
      case Kind::Double: return static_cast<double>(seq) * 0.5 + static_cast<double>(k) / 16.0;
      case Kind::String: return name + "-" + std::to_string(seq);
      case Kind::Struct: return structure(*schema.find(m.type_name));
    }
    return {};
  }

  Json array(const Member& m, const std::vector<int64_t>& lens, std::size_t level) {
    if (level == lens.size()) return element(m, m.name);
    Json a = Json::array();
    for (int64_t i = 0; i < lens[level]; ++i) a.push_back(array(m, lens, level + 1));
    return a;
  }

  Json structure(const Struct& s) {
    std::set<std::string> size_members;
    for (const Member& m : s.members)
      for (const Dim& d : m.dims)
        if (d.variable) size_members.insert(d.var);
    bool is_header = s.name == "header_t";
    Json obj = Json::object();
    std::map<std::string, int64_t> sizes;
    for (const Member& m : s.members) {
      if (is_header && m.name == "seq") {
        obj[m.name] = seq;
      } else if (is_header && m.name == "utime") {
        obj[m.name] = utime;
      } else if (size_members.count(m.name)) {
        // 0..12 elements: covers empty arrays and arrays long enough to be shortened in print.
        int64_t len = (seq * 7 + k++) % 13;
        sizes[m.name] = len;
        obj[m.name] = len;
      } else if (m.dims.empty()) {
        obj[m.name] = element(m, m.name);
      } else {
        std::vector<int64_t> lens;
        for (const Dim& d : m.dims) lens.push_back(d.variable ? sizes.at(d.var) : d.fixed);
        obj[m.name] = array(m, lens, 0);
      }
    }
    return obj;
  }
};

}  // namespace

Json sample_message(const Schema& schema, const Struct& type, int64_t seq, int64_t utime) {
  return Filler{schema, seq, utime}.structure(type);
}

std::string default_channel(const Struct& type) {
  namespace ch = hg::channels;
  static const std::map<std::string, const char*> table = {
      {"depth_frame_t", ch::kDepth},    {"plate_cloud_t", ch::kPlateCloud},
      {"outline_t", ch::kOutline},      {"part_pose_t", ch::kPartPose},
      {"grind_path_t", ch::kGrindPath}, {"job_request_t", ch::kJobRequest},
      {"job_status_t", ch::kJobStatus}, {"robot_status_t", ch::kRobotStatus},
      {"robot_move_t", ch::kRobotMove}, {"heartbeat_t", ch::kHeartbeat},
      {"log_line_t", ch::kLog}};
  auto it = table.find(type.name);
  return it == table.end() ? std::string() : std::string(it->second);
}

std::vector<const Struct*> message_types(const Schema& schema) {
  std::vector<const Struct*> out;
  for (const Struct& s : schema.structs())
    if (!default_channel(s).empty()) out.push_back(&s);
  return out;
}

int64_t message_seq(const Json& msg) {
  if (!msg.is_object()) return -1;
  auto h = msg.find("header");
  if (h != msg.end() && h->is_object() && h->contains("seq") && (*h)["seq"].is_number_integer())
    return (*h)["seq"].get<int64_t>();
  if (msg.contains("seq") && msg.contains("utime") && msg["seq"].is_number_integer()) return msg["seq"].get<int64_t>();
  return -1;
}

}  // namespace hg::lcmtools
