// Reads an LCM log file (the lcm-logger format: per event a sync word 0xEDA1DA01, event number, time in
// microseconds, channel length, data length, channel, data; all big endian) from memory. A corrupt event
// (bad sync word, impossible lengths, cut short) is counted and skipped: the reader scans for the next
// sync word that starts a well-formed event.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hg::foxglove {

struct LogEvent {
  std::int64_t number = 0;
  std::int64_t utime = 0;
  std::string_view channel;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

class LogReader {
 public:
  LogReader(const std::uint8_t* data, std::size_t size) : d_(data), size_(size) {}
  // The next event, or false at the end.
  bool next(LogEvent& e);
  std::size_t corrupt() const { return corrupt_; }                                 // corrupt stretches skipped
  std::size_t position() const { return pos_; }                                    // bytes read so far
  const std::vector<std::size_t>& corrupt_offsets() const { return corrupt_at_; }  // the first 10

 private:
  bool event_at(std::size_t pos, LogEvent& e, std::size_t& end) const;
  const std::uint8_t* d_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::size_t corrupt_ = 0;
  std::vector<std::size_t> corrupt_at_;
};

// A whole file mapped read-only; throws std::runtime_error naming the file.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace hg::foxglove
