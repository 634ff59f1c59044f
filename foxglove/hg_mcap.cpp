// hg-mcap: an LCM log as MCAP, with the live server's topics and schemas (docs/foxglove.md).
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>

#include "cell/cell.hpp"
#include "cell/cell_params.hpp"
#include "lcmlog.hpp"
#include "runtime/params.hpp"
#include "to_mcap.hpp"

namespace {

using hg::runtime::Param;

std::vector<Param> mcap_params() {
  Param output = hg::runtime::text_param("output", "", "the MCAP file to write (written to OUTPUT.tmp, then renamed)");
  output.alias = "-o";
  return {
      output,
      hg::runtime::text_param("compression", "zstd", "chunk compression", {"zstd", "lz4", "none"}),
      hg::runtime::integer_param("chunk-size", "4194304", "uncompressed bytes of messages per chunk", 1024, 1 << 30),
      hg::runtime::integer_param("max-points", "200000",
                                 "foxglove.PointCloud: at most this many points (every k-th; 0 = all)", 0, 1e9),
      hg::runtime::text_param("cell", "",
                              "cell file (config/cell.yaml): the base frame (frames.base) and the base <- camera "
                              "transform; empty: robot_base, no camera transform"),
      hg::runtime::integer_param("start-utime", "-9223372036854775807", "first event time kept, microseconds"),
      hg::runtime::integer_param("end-utime", "9223372036854775807", "last event time kept, microseconds"),
      hg::cell::moved_to_cell({{"base-frame", "frames.base"}}).front()};
}

void usage(std::FILE* f, const hg::runtime::Params& params) {
  std::fprintf(
      f,
      "usage: hg-mcap IN.lcmlog -o OUT.mcap [options]\n"
      "Writes an LCM log as MCAP for Foxglove and Lichtblick: every channel a topic with the JSON Schema\n"
      "generated from the .lcm files (encoding json), plus the 3-D picture in Foxglove's schemas\n"
      "(/hg/plate/points, /hg/outline, /hg/grind_path, /tf/camera, /tf); log times are the log's event times; chunked\n"
      "with message indexes and the summary section (docs/foxglove.md). A corrupt log event is counted,\n"
      "reported and skipped; a message of an unknown type is written raw (encoding lcm).\n"
      "Exit status: 0 written, 1 failed to write, 2 bad command line or input (not an LCM log).\n\n"
      "options:\n");
  params.print_options(f);
  std::fprintf(f, "  --help, --help-markdown, --version this text, the options as a Markdown table, the version\n");
}

hg::foxglove::ToMcapOptions options(const hg::runtime::Params& p) {
  hg::foxglove::ToMcapOptions o;
  o.mcap.compression = hg::foxglove::parse_compression(p.text("compression"));
  o.mcap.chunk_size = static_cast<std::size_t>(p.integer("chunk-size"));
  o.mcap.library = std::string("hullgrind hg-mcap ") + hg::runtime::version();
  o.bridge.max_points = static_cast<std::size_t>(p.integer("max-points"));
  if (!p.text("cell").empty()) {
    hg::cell::Cell cell = hg::cell::read_cell(p.text("cell"));
    o.bridge.base_frame = cell.frames.base;
    if (cell.calibration.camera_to_flange) o.bridge.camera_to_flange = cell.calibration.camera_to_flange;
    else
      o.bridge.camera_to_base = cell.calibration.camera_to_base;
  }
  o.start_utime = p.integer("start-utime");
  o.end_utime = p.integer("end-utime");
  return o;
}

void report(const std::string& in, const hg::foxglove::ToMcapStats& st, std::size_t in_bytes, double seconds) {
  std::fprintf(stderr,
               "hg-mcap: %s: %zu events -> %zu messages on %zu topics, %.1f MB -> %.1f MB in %.2f s (%.0f MB/s)\n",
               in.c_str(), st.events, st.messages, st.topics, in_bytes / 1e6, st.bytes_out / 1e6, seconds,
               seconds > 0 ? in_bytes / 1e6 / seconds : 0.0);
  if (st.corrupt) {
    std::fprintf(stderr, "hg-mcap: %s: %zu corrupt stretches skipped, the first at byte", in.c_str(), st.corrupt);
    for (std::size_t off : st.corrupt_offsets) std::fprintf(stderr, " %zu", off);
    std::fprintf(stderr, "\n");
  }
  if (st.decode_errors)
    std::fprintf(stderr, "hg-mcap: %s: %zu messages did not decode and were skipped; the first: %s\n", in.c_str(),
                 st.decode_errors, st.first_decode_error.c_str());
  if (st.decode_errors) {
    std::fprintf(stderr, "hg-mcap: %s: skipped events:", in.c_str());
    for (const auto& [channel, number] : st.skipped)
      std::fprintf(stderr, " %s#%lld", channel.c_str(), static_cast<long long>(number));
    std::fprintf(stderr, "\n");
  }
  if (st.unknown)
    std::fprintf(stderr, "hg-mcap: %s: %zu messages of an unknown type written raw\n", in.c_str(), st.unknown);
}

int convert(const hg::runtime::Params& p) {
  const std::string in = p.positional()[0], out = p.text("output");
  hg::foxglove::ToMcapOptions opt = options(p);
  hg::foxglove::MappedFile log(in);
  std::error_code ec;
  auto kind = std::filesystem::status(out, ec).type();
  if (kind != std::filesystem::file_type::not_found && kind != std::filesystem::file_type::regular)
    throw std::invalid_argument(out + ": exists and is not a regular file (it would be replaced)");
  const std::string tmp = out + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    std::fprintf(stderr, "hg-mcap: cannot write %s\n", tmp.c_str());
    return 1;
  }
  auto t0 = std::chrono::steady_clock::now();
  hg::foxglove::ToMcapStats st;
  try {
    st = hg::foxglove::lcmlog_to_mcap(log.data(), log.size(), f, opt);
  } catch (const std::exception& e) {
    std::fclose(f);
    std::filesystem::remove(tmp);
    std::fprintf(stderr, "hg-mcap: %s: %s\n", out.c_str(), e.what());
    return 1;
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (std::fclose(f) != 0) {
    std::filesystem::remove(tmp);
    std::fprintf(stderr, "hg-mcap: %s: write failed\n", out.c_str());
    return 1;
  }
  report(in, st, log.size(), seconds);
  if (st.events_read == 0 && log.size() > 0) {
    std::filesystem::remove(tmp);
    std::fprintf(stderr, "hg-mcap: %s: not an LCM log (no event in %zu bytes)\n", in.c_str(), log.size());
    return 2;
  }
  std::filesystem::rename(tmp, out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hg::runtime::Params params(mcap_params());
  try {
    const auto action = params.parse(argc, argv);
    if (action != hg::runtime::Params::Action::Run) return hg::runtime::answer(action, "hg-mcap", params, usage);
    if (params.positional().size() != 1 || params.text("output").empty())
      throw hg::runtime::ConfigError("command line: give one IN.lcmlog and -o OUT.mcap (see --help)");
    return convert(params);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hg-mcap: %s\n", e.what());
    return 2;
  }
}
