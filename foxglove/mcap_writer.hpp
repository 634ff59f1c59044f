// An MCAP writer (the format: mcap.dev/spec; no MCAP library is packaged for Debian 12).
// What it writes, in file order:
//   magic, Header, then the data section: Schema and Channel records (each before the first chunk that
//   uses it), Chunks (zstd, lz4 frame or uncompressed, each with the CRC32 of its uncompressed records),
//   each chunk followed by one Message Index per channel it holds; Data End (CRC32 of the file up to it);
//   the summary section: every Schema, every Channel, Statistics, one Chunk Index per chunk; the summary
//   offset section (one Summary Offset per group); Footer (CRC32 of summary and offsets); magic.
// Readers can therefore seek by time (chunk indexes, message indexes) and list channels and counts
// without reading the data.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hg::foxglove {

enum class Compression { None, Zstd, Lz4 };
Compression parse_compression(const std::string& name);  // "zstd" | "lz4" | "none"; std::invalid_argument
const char* compression_name(Compression c);             // as the Chunk record spells it ("" for none)

struct McapOptions {
  Compression compression = Compression::Zstd;
  std::size_t chunk_size = 4u << 20;  // uncompressed bytes of records per chunk before it is closed
  std::string library = "hullgrind";
};

class McapWriter {
 public:
  // Writes to out (opened binary by the caller, not closed). Throws std::runtime_error on a write error.
  McapWriter(std::FILE* out, McapOptions options);
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Ids start at 1 (0 means "no schema" for a channel).
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  // Times in nanoseconds since the epoch.
  void write_message(std::uint16_t channel, std::uint32_t sequence, std::uint64_t log_time, std::uint64_t publish_time,
                     const void* data, std::size_t size);
  // A message written in place: the caller appends its payload to the returned buffer (the open chunk),
  // then ends it with its channel and sequence, or cancels it (which drops whatever was appended). A cloud's
  // 36 MB of JSON text is then written once, not written and copied. No other message may come between.
  std::string& begin_message(std::uint64_t log_time, std::uint64_t publish_time);
  void end_message(std::uint16_t channel, std::uint32_t sequence);
  void cancel_message();
  // Closes the last chunk and writes the summary and the footer. Call once.
  void finish();

  std::uint64_t bytes_written() const { return offset_; }
  std::uint64_t message_count() const { return message_count_; }

 private:
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t index_length, compressed_size, uncompressed_size;
  };
  void write(const void* data, std::size_t size);  // to the file, counting the offset and the data CRC
  void record(std::uint8_t opcode, const std::string& content);
  void record_head(std::uint8_t opcode, std::uint64_t length);
  void flush_chunk();
  std::string schema_record(std::uint16_t id) const;
  std::string channel_record(std::uint16_t id) const;
  std::string statistics_record() const;
  std::string chunk_index_record(const ChunkIndex& c) const;

  struct Compressor;
  std::FILE* out_;
  McapOptions opt_;
  std::unique_ptr<Compressor> compressor_;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;
  bool finished_ = false;

  struct SchemaRec {
    std::string name, encoding, data;
  };
  struct ChannelRec {
    std::uint16_t schema_id;
    std::string topic, encoding;
    std::map<std::string, std::string> metadata;
  };
  std::vector<SchemaRec> schemas_;
  std::vector<ChannelRec> channels_;

  // The open chunk.
  std::string chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::size_t message_start_ = 0;  // of the message begun in place
  std::uint64_t message_time_ = 0;

  std::vector<ChunkIndex> chunks_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0, start_time_ = 0, end_time_ = 0;
};

}  // namespace hg::foxglove
