// LCM message -> JSON, and the JSON Schema of that JSON, both driven by one thing: the hullgrind schema
// parsed from the .lcm files (tools/lcm_tools, embedded at build time). No schema is written by hand, so a
// field added to a .lcm file appears in the schema and in every message at the next build.
//
// The mapping (JSON Schema draft-07, what ajv and Foxglove read):
//   int8..int64 -> integer (with the type's range), byte -> integer 0..255,
//   float, double -> number, or null for NaN/Inf (JSON has no such numbers; the schema says number, see
//   below), boolean -> boolean, string -> string (bytes that are not UTF-8 become U+FFFD),
//   byte arrays -> one base64 string (contentEncoding base64, as Foxglove's JSON encoding writes bytes),
//   other arrays -> arrays (fixed sizes as minItems = maxItems); an array of any rank is one flat array in
//   row-major order; nested struct -> object, its schema in place; every member is required and no other
//   property is allowed.
// The schema keeps to what Foxglove's and Lichtblick's JSON Schema reader takes (one "type" per field, no
// "$ref", no array of arrays): a channel whose schema a viewer refuses shows nothing.
// The encoder writes the text straight from the message bytes (no intermediate tree): a 1.6 M-point cloud
// is 5 M floats, and the live server and hg-mcap both run this on every message.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tools/lcm_tools/lcm_schema.hpp"

namespace hg::foxglove {

using lcmtools::Json;
using lcmtools::Schema;
using lcmtools::Struct;

// The JSON Schema of the JSON that to_json writes for messages of type s; "title" is the full type name.
Json json_schema(const Schema& schema, const Struct& s);

// Thrown by to_json when its cancel flag is set: the live server is stopping (its conversion runs at idle
// priority and may get no core for seconds; it gives up within a block of 1024 numbers).
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

// Appends the JSON text of one whole LCM message (fingerprint + body) of type s to out. Throws
// lcmtools::DecodeError (naming the field and byte offset) on a wrong fingerprint, truncated or lying
// lengths, or trailing bytes, and Cancelled once *cancel is true; out is then left with a partial text the
// caller discards.
void to_json(const Schema& schema, const Struct& s, const std::uint8_t* data, std::size_t size, std::string& out,
             const std::atomic<bool>* cancel = nullptr);

// Standard base64 (RFC 4648, with padding), appended to out.
void append_base64(const std::uint8_t* data, std::size_t size, std::string& out);
// The shortest text that reads back as v (a finite float or double: no NaN or Inf), in fixed or scientific
// notation, whichever is shorter; at most 24 characters ("-2.2250738585072014e-308"), written at p without a
// bound check, and up to 16 bytes past the end may be overwritten (room for 40 at p). Returns the end.
char* write_shortest(char* p, float v);
char* write_shortest(char* p, double v);
// A JSON string literal (quotes included) of text, appended to out; invalid UTF-8 becomes U+FFFD.
void append_json_string(std::string_view text, std::string& out);

}  // namespace hg::foxglove
