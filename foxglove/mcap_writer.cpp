#include "mcap_writer.hpp"

#include <libdeflate.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string_view>

namespace hg::foxglove {

namespace {

const uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Little-endian fields, as every MCAP integer is.
template <class T>
void put(std::string& s, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i)
    s.push_back(static_cast<char>((static_cast<uint64_t>(v) >> (8 * i)) & 0xFF));
}
void put_string(std::string& s, const std::string& v) {
  put<uint32_t>(s, static_cast<uint32_t>(v.size()));
  s += v;
}
std::string record_bytes(uint8_t opcode, const std::string& content) {
  std::string r;
  r.reserve(9 + content.size());
  r.push_back(static_cast<char>(opcode));
  put<uint64_t>(r, content.size());
  r += content;
  return r;
}
// libdeflate's CRC-32 (PCLMUL folding where the CPU has it: several times zlib's speed on a chunk of clouds).
uint32_t crc32_of(uint32_t crc, const void* data, std::size_t size) { return libdeflate_crc32(crc, data, size); }

}  // namespace

// The zstd context, made once: ZSTD_compress would allocate (and fault in) a context of several MB for
// every chunk (LZ4F_compressFrame's state is small). The output buffer only grows and is never filled
// first: a std::string's resize would write zeros over all of ZSTD_compressBound (the size of a cloud's
// chunk, 36 MB) and copy the old bytes, faulting in every page of it, where the compressed chunk (6 MB)
// touches only the pages it writes (docs/BENCHMARKS.md, "hg-mcap").
// Level 1 with a hash table of 2^10 entries instead of level 1's 2^13: 4 kB, which stays in the L1 cache. On
// the JSON text of clouds decimated to the default 200 k points its chunks are 4 % smaller than with 2^12,
// with every point kept 12 % larger, at the same CPU time (docs/BENCHMARKS.md, "hg-mcap").
struct McapWriter::Compressor {
  ZSTD_CCtx* zstd = ZSTD_createCCtx();
  std::unique_ptr<char[]> out;
  std::size_t capacity = 0;
  Compressor() {
    if (!zstd || ZSTD_isError(ZSTD_CCtx_setParameter(zstd, ZSTD_c_compressionLevel, 1)) ||
        ZSTD_isError(ZSTD_CCtx_setParameter(zstd, ZSTD_c_hashLog, 10)))
      throw std::runtime_error("cannot make a zstd context");
  }
  ~Compressor() { ZSTD_freeCCtx(zstd); }

  // What the chunk holds: the compressed bytes, or `in` itself when uncompressed.
  std::string_view compress(Compression c, const std::string& in) {
    if (c == Compression::Zstd) {
      reserve(ZSTD_compressBound(in.size()));
      std::size_t n = ZSTD_compress2(zstd, out.get(), capacity, in.data(), in.size());
      if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
      return {out.get(), n};
    }
    if (c == Compression::Lz4) {
      LZ4F_preferences_t prefs{};
      prefs.frameInfo.contentSize = in.size();
      reserve(LZ4F_compressFrameBound(in.size(), &prefs));
      std::size_t n = LZ4F_compressFrame(out.get(), capacity, in.data(), in.size(), &prefs);
      if (LZ4F_isError(n)) throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(n));
      return {out.get(), n};
    }
    return in;
  }
  void reserve(std::size_t n) {
    if (capacity >= n) return;
    out.reset(new char[n]);  // not value-initialised: no page is touched before the compressor writes it
    capacity = n;
  }
};

Compression parse_compression(const std::string& name) {
  if (name == "zstd") return Compression::Zstd;
  if (name == "lz4") return Compression::Lz4;
  if (name == "none") return Compression::None;
  throw std::invalid_argument("compression must be zstd, lz4 or none, not '" + name + "'");
}

const char* compression_name(Compression c) {
  return c == Compression::Zstd ? "zstd" : c == Compression::Lz4 ? "lz4" : "";
}

McapWriter::McapWriter(std::FILE* out, McapOptions options)
    : out_(out), opt_(std::move(options)), compressor_(std::make_unique<Compressor>()) {
  write(kMagic, sizeof kMagic);
  std::string h;
  put_string(h, "");  // profile: none of the registered ones (ros1, ros2) applies
  put_string(h, opt_.library);
  record(kHeader, h);
}

McapWriter::~McapWriter() = default;

void McapWriter::write(const void* data, std::size_t size) {
  if (size == 0) return;
  if (std::fwrite(data, 1, size, out_) != size) throw std::runtime_error("write failed");
  if (!finished_) data_crc_ = crc32_of(data_crc_, data, size);
  offset_ += size;
}

void McapWriter::record(uint8_t opcode, const std::string& content) {
  record_head(opcode, content.size());
  write(content.data(), content.size());
}

void McapWriter::record_head(uint8_t opcode, uint64_t length) {
  std::string h;
  h.push_back(static_cast<char>(opcode));
  put<uint64_t>(h, length);
  write(h.data(), h.size());
}

std::string McapWriter::schema_record(uint16_t id) const {
  const SchemaRec& s = schemas_[id - 1];
  std::string c;
  put<uint16_t>(c, id);
  put_string(c, s.name);
  put_string(c, s.encoding);
  put_string(c, s.data);  // bytes: uint32 length + data, as a string is
  return c;
}

std::string McapWriter::channel_record(uint16_t id) const {
  const ChannelRec& ch = channels_[id - 1];
  std::string c, map;
  put<uint16_t>(c, id);
  put<uint16_t>(c, ch.schema_id);
  put_string(c, ch.topic);
  put_string(c, ch.encoding);
  for (const auto& [k, v] : ch.metadata) {
    put_string(map, k);
    put_string(map, v);
  }
  put_string(c, map);  // a map is its byte length and the entries
  return c;
}

uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (schemas_.size() >= 0xFFFE) throw std::runtime_error("too many schemas");
  schemas_.push_back({name, encoding, data});
  auto id = static_cast<uint16_t>(schemas_.size());
  record(kSchema, schema_record(id));
  return id;
}

uint16_t McapWriter::add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  if (channels_.size() >= 0xFFFE) throw std::runtime_error("too many channels");
  channels_.push_back({schema_id, topic, message_encoding, metadata});
  auto id = static_cast<uint16_t>(channels_.size());
  record(kChannel, channel_record(id));
  return id;
}

void McapWriter::write_message(uint16_t channel, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
                               const void* data, std::size_t size) {
  begin_message(log_time, publish_time).append(static_cast<const char*>(data), size);
  end_message(channel, sequence);
}

// The message record's head with its length, channel and sequence still zero: end_message fills them in.
std::string& McapWriter::begin_message(uint64_t log_time, uint64_t publish_time) {
  message_start_ = chunk_.size();
  message_time_ = log_time;
  chunk_.push_back(static_cast<char>(kMessage));
  put<uint64_t>(chunk_, 0);
  put<uint16_t>(chunk_, 0);
  put<uint32_t>(chunk_, 0);
  put<uint64_t>(chunk_, log_time);
  put<uint64_t>(chunk_, publish_time);
  return chunk_;
}

void McapWriter::cancel_message() { chunk_.resize(message_start_); }

void McapWriter::end_message(uint16_t channel, uint32_t sequence) {
  const uint64_t log_time = message_time_;
  std::string fields;
  put<uint64_t>(fields, chunk_.size() - message_start_ - 9);  // the record's length: all after opcode and length
  put<uint16_t>(fields, channel);
  put<uint32_t>(fields, sequence);
  std::memcpy(chunk_.data() + message_start_ + 1, fields.data(), fields.size());
  if (message_start_ == 0) chunk_start_ = chunk_end_ = log_time;
  chunk_index_[channel].emplace_back(log_time, message_start_);
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  if (message_count_ == 0) start_time_ = end_time_ = log_time;
  start_time_ = std::min(start_time_, log_time);
  end_time_ = std::max(end_time_, log_time);
  ++message_count_;
  ++channel_counts_[channel];
  if (chunk_.size() >= opt_.chunk_size) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  ChunkIndex ci{chunk_start_, chunk_end_, offset_, 0, {}, 0, 0, chunk_.size()};
  const std::string_view body = compressor_->compress(opt_.compression, chunk_);
  std::string c;
  put<uint64_t>(c, chunk_start_);
  put<uint64_t>(c, chunk_end_);
  put<uint64_t>(c, chunk_.size());
  put<uint32_t>(c, crc32_of(0, chunk_.data(), chunk_.size()));
  put_string(c, compression_name(opt_.compression));
  put<uint64_t>(c, body.size());                // records: uint64 length + bytes
  record_head(kChunk, c.size() + body.size());  // the body is written as it is, not copied into c
  write(c.data(), c.size());
  write(body.data(), body.size());
  ci.length = offset_ - ci.offset;
  ci.compressed_size = body.size();
  uint64_t index_start = offset_;
  for (auto& [channel, entries] : chunk_index_) {
    std::stable_sort(entries.begin(), entries.end(), [](auto& a, auto& b) { return a.first < b.first; });
    std::string m;
    put<uint16_t>(m, channel);
    put<uint32_t>(m, static_cast<uint32_t>(entries.size() * 16));
    for (auto [t, off] : entries) {
      put<uint64_t>(m, t);
      put<uint64_t>(m, off);
    }
    ci.index_offsets[channel] = offset_;
    record(kMessageIndex, m);
  }
  ci.index_length = offset_ - index_start;
  chunks_.push_back(std::move(ci));
  chunk_.clear();
  chunk_index_.clear();
}

std::string McapWriter::statistics_record() const {
  std::string c, map;
  put<uint64_t>(c, message_count_);
  put<uint16_t>(c, static_cast<uint16_t>(schemas_.size()));
  put<uint32_t>(c, static_cast<uint32_t>(channels_.size()));
  put<uint32_t>(c, 0);  // attachments
  put<uint32_t>(c, 0);  // metadata
  put<uint32_t>(c, static_cast<uint32_t>(chunks_.size()));
  put<uint64_t>(c, start_time_);
  put<uint64_t>(c, end_time_);
  for (const auto& [channel, n] : channel_counts_) {
    put<uint16_t>(map, channel);
    put<uint64_t>(map, n);
  }
  put_string(c, map);
  return c;
}

std::string McapWriter::chunk_index_record(const ChunkIndex& ci) const {
  std::string c, map;
  put<uint64_t>(c, ci.start_time);
  put<uint64_t>(c, ci.end_time);
  put<uint64_t>(c, ci.offset);
  put<uint64_t>(c, ci.length);
  for (const auto& [channel, off] : ci.index_offsets) {
    put<uint16_t>(map, channel);
    put<uint64_t>(map, off);
  }
  put_string(c, map);
  put<uint64_t>(c, ci.index_length);
  put_string(c, compression_name(opt_.compression));
  put<uint64_t>(c, ci.compressed_size);
  put<uint64_t>(c, ci.uncompressed_size);
  return c;
}

void McapWriter::finish() {
  if (finished_) return;
  flush_chunk();
  std::string de;
  put<uint32_t>(de, data_crc_);
  finished_ = true;  // the data CRC covers everything before Data End
  record(kDataEnd, de);

  // The summary is built in memory first: its CRC covers it, the offsets and the footer's first fields.
  uint64_t summary_start = offset_;
  std::string summary, offsets;
  auto group = [&](uint8_t opcode, const std::vector<std::string>& contents) {
    if (contents.empty()) return;
    uint64_t start = summary_start + summary.size();
    for (const std::string& c : contents) summary += record_bytes(opcode, c);
    std::string so;
    so.push_back(static_cast<char>(opcode));
    put<uint64_t>(so, start);
    put<uint64_t>(so, summary_start + summary.size() - start);
    offsets += record_bytes(kSummaryOffset, so);
  };
  std::vector<std::string> recs;
  for (std::size_t i = 1; i <= schemas_.size(); ++i) recs.push_back(schema_record(static_cast<uint16_t>(i)));
  group(kSchema, recs);
  recs.clear();
  for (std::size_t i = 1; i <= channels_.size(); ++i) recs.push_back(channel_record(static_cast<uint16_t>(i)));
  group(kChannel, recs);
  group(kStatistics, {statistics_record()});
  recs.clear();
  for (const ChunkIndex& ci : chunks_) recs.push_back(chunk_index_record(ci));
  group(kChunkIndex, recs);

  uint64_t offsets_start = summary_start + summary.size();
  std::string footer;
  put<uint64_t>(footer, summary_start);
  put<uint64_t>(footer, offsets_start);
  std::string covered = summary + offsets;
  covered.push_back(static_cast<char>(kFooter));
  put<uint64_t>(covered, 8 + 8 + 4);
  covered += footer;
  put<uint32_t>(footer, crc32_of(0, covered.data(), covered.size()));
  write(summary.data(), summary.size());
  write(offsets.data(), offsets.size());
  record(kFooter, footer);
  write(kMagic, sizeof kMagic);
  if (std::fflush(out_) != 0) throw std::runtime_error("write failed");
}

}  // namespace hg::foxglove
