// The hullgrind LCM schema read from the .lcm files, and a decoder/encoder driven by it.
// Why: lcm-gen's C++ classes have no reflection, so printing any message as JSON (hg-lcm-dump) or
// building a sample of any type (hg-lcm-send) needs the field list. The schema is embedded at build time
// from the same .lcm files the classes come from; registry.cpp checks both give the same fingerprints.
// The decoder never trusts a length from the wire: every array or string is checked against the bytes
// left before anything is allocated (lcm-gen's decode resizes vectors first), so garbage cannot make it
// allocate or crash.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace hg::lcmtools {
// Objects keep the schema's field order, so printed messages read like the .lcm file.
using Json = nlohmann::ordered_json;
}  // namespace hg::lcmtools

namespace hg::lcmtools {

enum class Kind { Int8, Int16, Int32, Int64, Float, Double, String, Boolean, Byte, Struct };

struct Dim {
  bool variable = false;  // size read from an earlier integer member of the same struct
  int64_t fixed = 0;      // size when !variable
  std::string var;        // that member's name when variable
};

struct Member {
  std::string name;
  Kind kind = Kind::Int8;
  std::string type_name;  // as written ("double", "header_t"); full name "pkg.name" for structs after parse
  std::vector<Dim> dims;
};

struct Struct {
  std::string package;
  std::string name;
  std::vector<Member> members;
  std::string source;  // "file.lcm", for messages
  std::string full_name() const { return package.empty() ? name : package + "." + name; }
};

struct SchemaSource {
  const char* name;
  const char* text;
};

// The .lcm files this binary was built with.
const std::vector<SchemaSource>& embedded_schema_sources();

class SchemaError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
class DecodeError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DecodeOptions {
  bool full = false;          // print every array element
  std::size_t max_shown = 8;  // else an array longer than this prints {"length": n, "first": [...]}
};

class Schema {
 public:
  // Parses one .lcm file; errors name source:line.
  void add(std::string_view text, const std::string& source_name);
  // Resolves struct member types across files; call after the last add().
  void finish();
  static Schema embedded();

  const std::vector<Struct>& structs() const { return structs_; }
  const Struct* find(std::string_view name) const;  // "hullgrind.heartbeat_t" or "heartbeat_t"
  const Struct* find_by_fingerprint(int64_t fingerprint) const;

  // The fingerprint LCM puts in the first 8 bytes of a message, computed from the schema alone.
  int64_t fingerprint(const Struct& s) const;

  // Decodes a whole message (fingerprint + body) of type s. Returns the fields; `consumed` gets the bytes
  // used. Throws DecodeError naming the field and byte offset.
  Json decode(const Struct& s, const uint8_t* data, std::size_t size, std::size_t& consumed,
              const DecodeOptions& opt) const;
  // Encodes a full JSON value of s (as decode with full=true prints it) into a message with fingerprint.
  std::vector<uint8_t> encode(const Struct& s, const Json& value) const;

 private:
  uint64_t base_hash(const Struct& s) const;
  uint64_t recursive_hash(const Struct& s, std::vector<const Struct*>& parents) const;

  std::vector<Struct> structs_;
  std::map<int64_t, std::size_t> by_fingerprint_;
};

bool is_primitive(Kind k);
const char* kind_name(Kind k);

}  // namespace hg::lcmtools
