#include "to_mcap.hpp"

#include "lcmlog.hpp"

namespace hg::foxglove {

namespace {

struct Sink {
  McapWriter& w;
  std::vector<int> channel_of;  // bridge topic -> MCAP channel id
  std::map<std::string, std::uint16_t> schema_ids;
  std::vector<std::uint32_t> sequence;

  void add(const Topic& t, std::size_t index) {
    std::uint16_t schema = 0;
    if (!t.schema_name.empty()) {
      std::string key = t.schema_name + '\0' + t.schema;
      auto it = schema_ids.find(key);
      schema = it != schema_ids.end() ? it->second
                                      : (schema_ids[key] = w.add_schema(t.schema_name, t.schema_encoding, t.schema));
    }
    if (channel_of.size() <= index) channel_of.resize(index + 1, -1), sequence.resize(index + 1, 0);
    channel_of[index] = w.add_channel(schema, t.name, t.encoding);
  }
};

}  // namespace

ToMcapStats lcmlog_to_mcap(const std::uint8_t* log, std::size_t size, std::FILE* out, const ToMcapOptions& opt) {
  ToMcapStats st;
  McapWriter writer(out, opt.mcap);
  Bridge bridge(lcmtools::Schema::embedded(), opt.bridge);
  Sink sink{writer, {}, {}, {}};
  LogReader reader(log, size);
  LogEvent e;
  while (reader.next(e)) {
    ++st.events_read;
    if (e.utime < opt.start_utime || e.utime > opt.end_utime) continue;
    ++st.events;
    std::string channel(e.channel);
    auto time = static_cast<std::uint64_t>(std::max<std::int64_t>(0, e.utime)) * 1000;
    // The channel's own JSON goes straight into the open chunk (a cloud's text is written once, not copied).
    Converted c = bridge.convert(channel, e.data, e.size, nullptr, &writer.begin_message(time, time));
    for (int t : c.new_topics) sink.add(bridge.topics()[t], static_cast<std::size_t>(t));
    if (c.outputs.empty() || !c.outputs.front().in_place) writer.cancel_message();
    if (c.unknown_type) ++st.unknown;
    if (!c.error.empty()) {
      if (st.skipped.size() < 100) st.skipped.emplace_back(channel, e.number);
      if (st.decode_errors++ == 0)
        st.first_decode_error = channel + " event " + std::to_string(e.number) + ": " + c.error;
      continue;
    }
    for (Output& o : c.outputs) {
      const auto mcap_channel = static_cast<std::uint16_t>(sink.channel_of[o.topic]);
      if (o.in_place) writer.end_message(mcap_channel, sink.sequence[o.topic]++);
      else
        writer.write_message(mcap_channel, sink.sequence[o.topic]++, time, time, o.payload.data(), o.payload.size());
      ++st.per_topic[bridge.topics()[o.topic].name];
      ++st.messages;
      bridge.recycle(std::move(o.payload));
    }
  }
  writer.finish();
  st.corrupt = reader.corrupt();
  st.corrupt_offsets = reader.corrupt_offsets();
  st.topics = bridge.topics().size();
  st.bytes_out = writer.bytes_written();
  return st;
}

}  // namespace hg::foxglove
