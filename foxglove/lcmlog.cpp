#include "lcmlog.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hg::foxglove {

namespace {

constexpr std::uint32_t kSync = 0xEDA1DA01;
constexpr std::size_t kHeader = 4 + 8 + 8 + 4 + 4;
constexpr std::int64_t kMaxChannel = 256;  // LCM channel names are short; a longer one is garbage

std::uint64_t be(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

bool LogReader::event_at(std::size_t pos, LogEvent& e, std::size_t& end) const {
  if (size_ - pos < kHeader || be(d_ + pos, 4) != kSync) return false;
  const std::uint8_t* p = d_ + pos + 4;
  auto channel_len = static_cast<std::int32_t>(be(p + 16, 4));
  auto data_len = static_cast<std::int32_t>(be(p + 20, 4));
  if (channel_len <= 0 || channel_len > kMaxChannel || data_len < 0) return false;
  std::size_t need = kHeader + static_cast<std::size_t>(channel_len) + static_cast<std::size_t>(data_len);
  if (size_ - pos < need) return false;
  e.number = static_cast<std::int64_t>(be(p, 8));
  e.utime = static_cast<std::int64_t>(be(p + 8, 8));
  e.channel =
      std::string_view(reinterpret_cast<const char*>(d_ + pos + kHeader), static_cast<std::size_t>(channel_len));
  e.data = d_ + pos + kHeader + channel_len;
  e.size = static_cast<std::size_t>(data_len);
  end = pos + need;
  return true;
}

bool LogReader::next(LogEvent& e) {
  if (pos_ >= size_) return false;
  std::size_t end = 0;
  if (event_at(pos_, e, end)) {
    pos_ = end;
    return true;
  }
  if (corrupt_at_.size() < 10) corrupt_at_.push_back(pos_);
  ++corrupt_;  // one stretch of garbage, however long: scan to the next event that parses
  for (std::size_t p = pos_ + 1; p + kHeader <= size_; ++p) {
    if (d_[p] != 0xED) continue;
    if (event_at(p, e, end)) {
      pos_ = end;
      return true;
    }
  }
  pos_ = size_;
  return false;
}

MappedFile::MappedFile(const std::string& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error(path + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw std::runtime_error(path + ": not a regular file");
  }
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > 0) {
    void* m = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (m == MAP_FAILED) {
      ::close(fd);
      throw std::runtime_error(path + ": " + std::strerror(errno));
    }
    ::madvise(m, size_, MADV_SEQUENTIAL);
    data_ = static_cast<const std::uint8_t*>(m);
  }
  ::close(fd);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

}  // namespace hg::foxglove
