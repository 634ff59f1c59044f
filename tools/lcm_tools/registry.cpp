#include "registry.hpp"

#include <cstdio>

#include "hg_lcm_registry.inc"

namespace hg::lcmtools {

const std::vector<GeneratedType>& generated_types() {
#define HG_GENERATED_ENTRY(T)                                                              \
  GeneratedType{"hullgrind." #T, hullgrind::T::getHash(), [](const void* data, int size) { \
                  hullgrind::T m;                                                          \
                  return m.decode(data, 0, size);                                          \
                }},
  static const std::vector<GeneratedType> types = {HG_LCM_FOR_EACH_TYPE(HG_GENERATED_ENTRY)};
#undef HG_GENERATED_ENTRY
  return types;
}

void check_schema_matches_generated(const Schema& schema) {
  for (const GeneratedType& g : generated_types()) {
    const Struct* s = schema.find(g.full_name);
    if (!s) throw SchemaError("generated type " + g.full_name + " is missing from the embedded schema");
    if (schema.fingerprint(*s) != g.fingerprint)
      throw SchemaError("fingerprint of " + g.full_name + " differs between schema and generated class");
  }
  if (schema.structs().size() != generated_types().size())
    throw SchemaError("the embedded schema has " + std::to_string(schema.structs().size()) + " types, lcm-gen made " +
                      std::to_string(generated_types().size()));
}

Decoded decode_message(const Schema& schema, const uint8_t* data, std::size_t size, const DecodeOptions& opt) {
  Decoded out;
  if (size < 8) {
    out.error = "message of " + std::to_string(size) + " bytes is shorter than a fingerprint";
    return out;
  }
  int64_t fp = 0;
  for (int i = 0; i < 8; ++i) fp = static_cast<int64_t>((static_cast<uint64_t>(fp) << 8) | data[i]);
  const GeneratedType* gen = nullptr;
  for (const GeneratedType& g : generated_types())
    if (g.fingerprint == fp) gen = &g;
  if (!gen) {
    char hex[32];
    std::snprintf(hex, sizeof hex, "0x%016llx", static_cast<unsigned long long>(fp));
    out.error = std::string("unknown fingerprint ") + hex;
    return out;
  }
  const Struct* s = schema.find(gen->full_name);
  try {
    std::size_t used = 0;
    out.msg = schema.decode(*s, data, size, used, opt);
    if (used != size) {
      out.error =
          gen->full_name + ": " + std::to_string(size - used) + " trailing bytes after byte " + std::to_string(used);
      return out;
    }
  } catch (const DecodeError& e) {
    out.error = gen->full_name + ": " + e.what();
    return out;
  }
  // The schema already proved every length fits, so the generated decoder cannot over-allocate here.
  int used = -1;
  try {
    used = size > static_cast<std::size_t>(INT32_MAX) ? -1 : gen->decode(data, static_cast<int>(size));
  } catch (const std::exception& e) {
    used = -1;
  }
  if (used != static_cast<int>(size)) {
    out.error = gen->full_name + ": the generated decoder disagrees with the schema (used " + std::to_string(used) +
                " of " + std::to_string(size) + " bytes)";
    out.msg = nullptr;
    return out;
  }
  out.type = s;
  return out;
}

}  // namespace hg::lcmtools
