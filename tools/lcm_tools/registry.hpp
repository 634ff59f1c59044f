// The lcm-gen C++ classes of every hullgrind type, looked up by fingerprint, and the one decode path the
// tools use: schema decode first (bounds every length), then the generated class must agree byte for byte.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lcm_schema.hpp"

namespace hg::lcmtools {

struct GeneratedType {
  std::string full_name;  // "hullgrind.heartbeat_t"
  int64_t fingerprint;    // the class's getHash()
  // Decodes with the generated class; the bytes used, or < 0 if it refuses.
  int (*decode)(const void* data, int size);
};

const std::vector<GeneratedType>& generated_types();

// Checks that the embedded schema and the generated classes describe the same types (same names, same
// fingerprints); throws SchemaError naming the first difference.
void check_schema_matches_generated(const Schema& schema);

struct Decoded {
  const Struct* type = nullptr;  // null when decoding failed
  Json msg;
  std::string error;  // why, when type is null
};

// Never throws on bad bytes: unknown fingerprint, truncation, lying lengths and trailing bytes come back
// as an error text naming the byte offset.
Decoded decode_message(const Schema& schema, const uint8_t* data, std::size_t size, const DecodeOptions& opt);

}  // namespace hg::lcmtools
