// A plant-side DDS participant for the security tests, one per process (Cyclone takes one security
// configuration per domain and process). It tries to read the outline topic and to write job requests
// for a while, then prints what it managed:
//   reader ok | reader refused: WHY
//   writer ok | writer refused: WHY
//   outline_samples N
//   job_writes N
// usage: dds_peer DOMAIN CYCLONE_CONFIG PREFIX JOB_ID SECONDS [SECURITY_DIR IDENTITY]
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "dds_gateway/dds_support.hpp"

using namespace hg::dds_gateway;

int main(int argc, char** argv) {
  if (argc != 6 && argc != 8) {
    std::fprintf(stderr, "usage: %s DOMAIN CYCLONE_CONFIG PREFIX JOB_ID SECONDS [SECURITY_DIR IDENTITY]\n", argv[0]);
    return 2;
  }
  int domain = std::stoi(argv[1]);
  std::string config = argv[2], prefix = argv[3], job_id = argv[4];
  double seconds = std::stod(argv[5]);
  SecurityFiles sec;
  if (argc == 8) {
    std::string dir = argv[6], id = argv[7];
    sec = {dir + "/identity_ca.pem",    dir + "/" + id + ".pem", dir + "/" + id + ".key",
           dir + "/permissions_ca.pem", dir + "/governance.p7s", dir + "/" + id + "_permissions.p7s"};
  }
  dds_entity_t pp = 0;
  try {
    pp = make_participant(domain, config, sec);
  } catch (const std::exception& e) {
    std::printf("participant refused: %s\n", e.what());
    return 3;
  }
  dds_entity_t reader = 0, writer = 0;
  Qos state = state_qos(), stream = stream_qos();
  try {
    reader = make_reader(pp, make_topic(pp, &hgdds_Outline_desc, prefix + topic::kOutline), state.get());
    std::printf("reader ok\n");
  } catch (const std::exception& e) {
    std::printf("reader refused: %s\n", e.what());
  }
  try {
    writer = make_writer(pp, make_topic(pp, &hgdds_JobRequest_desc, prefix + topic::kJobRequest), stream.get());
    std::printf("writer ok\n");
  } catch (const std::exception& e) {
    std::printf("writer refused: %s\n", e.what());
  }
  int outline_samples = 0, job_writes = 0;
  auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (writer > 0) {
      hgdds_JobRequest r{};
      r.header.frame_id = const_cast<char*>("");
      r.job_id = const_cast<char*>(job_id.c_str());
      r.part_id = const_cast<char*>("peer");
      if (dds_write(writer, &r) >= 0) ++job_writes;
    }
    if (reader > 0) {
      void* samples[8] = {nullptr};
      dds_sample_info_t infos[8];
      dds_return_t n = dds_take(reader, samples, infos, 8, 8);
      for (int i = 0; i < n; ++i) outline_samples += infos[i].valid_data ? 1 : 0;
      if (n > 0) dds_return_loan(reader, samples, n);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::printf("outline_samples %d\njob_writes %d\n", outline_samples, job_writes);
  std::fflush(stdout);
  dds_delete(pp);
  return 0;
}
