// 1,000 part poses per second for 30 s, LCM -> hg-dds-gateway -> DDS: every one crosses exactly once
// (counted by header.seq), in order. Prints the figures; asserts no timing. And a burst that arrives while
// the gateway's loop is held up (the process stopped) crosses whole.
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "helpers.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/part_pose_t.hpp"

using namespace hgtest;
using namespace hg::dds_gateway;

namespace {

// The reader seeing the gateway's writer does not mean the writer has seen the reader yet, and a volatile
// writer sends nothing to a reader it does not know: warm up until a part pose crosses.
::testing::AssertionResult warm_up(lcm::LCM& lcm, Reader<hgdds_PartPose>& reader) {
  if (!wait_until([&] { return reader.matched() > 0; }, [] { std::this_thread::sleep_for(10ms); }, 20s))
    return ::testing::AssertionFailure() << "the gateway's part-pose writer was not matched";
  hullgrind::part_pose_t w{};
  w.header.seq = -1;
  w.header.frame_id = "warm-up";
  if (!wait_until([&] { return reader.take() > 0; },
                  [&] {
                    lcm.publish("HG_PART_POSE", &w);
                    std::this_thread::sleep_for(20ms);
                  },
                  20s))
    return ::testing::AssertionFailure() << "no part pose crossed during warm-up";
  std::this_thread::sleep_for(200ms);
  reader.take();  // late warm-up samples
  reader.samples.clear();
  return ::testing::AssertionSuccess();
}

// Datagrams the kernel dropped because a UDP socket's receive buffer was full, in this network namespace
// (/proc/net/snmp, Udp RcvbufErrors): tells a socket's loss from a loss inside a process.
long long udp_receive_buffer_errors() {
  std::ifstream in("/proc/net/snmp");
  std::string names, values, line;
  while (std::getline(in, line)) {
    if (line.rfind("Udp: ", 0) != 0) continue;
    if (names.empty()) names = line;
    else
      values = line;
  }
  std::istringstream n(names), v(values);
  std::string name, value;
  while (n >> name && v >> value)
    if (name == "RcvbufErrors") return std::stoll(value);
  return -1;
}

// The state letter of /proc/PID/stat ('T': stopped).
char process_state(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto close = stat.rfind(')');
  return close != std::string::npos && close + 2 < stat.size() ? stat[close + 2] : '?';
}

TEST(DdsGatewayThroughput, ThousandPerSecondForThirtySecondsNoLossNoDuplicate) {
  constexpr int kRate = 1000, kSeconds = 30, kTotal = kRate * kSeconds;
  constexpr int kDomain = 0;
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  ASSERT_TRUE(lcm.good());
  GatewayProcess gateway(kDomain);
  Collector<hullgrind::heartbeat_t> beats(lcm, "HG_HEARTBEAT");
  dds_entity_t pp = make_participant(kDomain, cyclone_config(), {});
  Qos q = stream_qos();
  Reader<hgdds_PartPose> reader(pp, &hgdds_PartPose_desc, "hg_part_pose", q.get());
  ASSERT_TRUE(warm_up(lcm, reader));

  // Count in a reader thread while this thread publishes at the pace.
  std::vector<int> seen(kTotal, 0);
  std::atomic<int> received{0}, out_of_range{0}, out_of_order{0};
  std::atomic<bool> stop{false};
  std::thread counter([&] {
    long long last = -1;
    while (!stop.load()) {
      void* samples[64] = {nullptr};
      dds_sample_info_t infos[64];
      dds_return_t n = dds_take(reader.get(), samples, infos, 64, 64);
      if (n <= 0) {
        std::this_thread::sleep_for(1ms);
        continue;
      }
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto* pose = static_cast<hgdds_PartPose*>(samples[i]);
        if (std::string(pose->header.frame_id) == "warm-up") continue;
        long long seq = pose->header.seq;
        if (seq < 0 || seq >= kTotal) {
          ++out_of_range;
          continue;
        }
        if (seq <= last) ++out_of_order;
        last = seq;
        ++seen[seq];
        ++received;
      }
      dds_return_loan(reader.get(), samples, n);
    }
  });

  auto t0 = Clock::now();
  hullgrind::part_pose_t m{};
  m.header.frame_id = "camera";
  m.num_parts = 1;
  for (int i = 0; i < kTotal; ++i) {
    std::this_thread::sleep_until(t0 + std::chrono::microseconds(1000000LL * i / kRate));
    m.header.seq = i;
    m.header.utime = hg::runtime::now_utime();
    m.area = 0.001 * i;
    ASSERT_EQ(lcm.publish("HG_PART_POSE", &m), 0);
  }
  double send_s = std::chrono::duration<double>(Clock::now() - t0).count();
  wait_until([&] { return received.load() >= kTotal; }, [] { std::this_thread::sleep_for(10ms); }, 30s);
  std::this_thread::sleep_for(200ms);  // a duplicate would arrive right behind
  stop = true;
  counter.join();
  double total_s = std::chrono::duration<double>(Clock::now() - t0).count();

  // Where a loss would have happened: the gateway's own counters (LCM messages decoded, DDS writes, drops).
  // (A heartbeat made after the counting finished, not one queued while this thread was publishing.)
  const int64_t counted_utime = hg::runtime::now_utime();
  auto last_beat = [&]() -> const hullgrind::heartbeat_t* {
    for (auto it = beats.msgs.rbegin(); it != beats.msgs.rend(); ++it)
      if (it->pid == gateway.pid() && it->header.utime > counted_utime) return &*it;
    return nullptr;
  };
  wait_until([&] { return last_beat() != nullptr; }, [&] { lcm.handleTimeout(20); }, 5s);
  // (Its counters cover every channel: the part poses, the warm-up ones and its own heartbeats, one a second.)
  if (const hullgrind::heartbeat_t* b = last_beat())
    std::printf(
        "[ FIGURES  ] gateway counters, all channels: received %lld, published %lld, dropped %lld,"
        " decode errors %lld\n",
        (long long)b->received, (long long)b->published, (long long)b->dropped, (long long)b->decode_errors);
  std::printf("[ FIGURES  ] kernel UDP receive-buffer drops in this namespace: %lld\n", udp_receive_buffer_errors());
  int missing = 0, duplicated = 0;
  std::string first_missing;
  for (int i = 0; i < kTotal; ++i) {
    if (seen[i] == 0 && ++missing <= 10) first_missing += " " + std::to_string(i);
    duplicated += seen[i] > 1;
  }
  if (missing) std::printf("[ FIGURES  ] first missing seqs:%s\n", first_missing.c_str());
  std::printf(
      "[ FIGURES  ] %d part poses published in %.2f s (%.0f/s); %d received on DDS, %d missing, %d duplicated,"
      " %d out of order; all in after %.2f s\n",
      kTotal, send_s, kTotal / send_s, received.load(), missing, duplicated, out_of_order.load(), total_s);
  EXPECT_EQ(missing, 0);
  EXPECT_EQ(duplicated, 0);
  EXPECT_EQ(out_of_range.load(), 0);
  EXPECT_EQ(out_of_order.load(), 0);
  EXPECT_TRUE(gateway.running());
  dds_delete(pp);
}

// While the gateway's loop is held up, LCM must keep what arrives for it: here the whole process is stopped
// while a burst of 1,000 part poses (1 s of the stream, far more than LCM's default queue of 30) arrives in
// its socket; after it continues, every one crosses exactly once. (Its own topic prefix: no sample of
// another test can count.)
TEST(DdsGatewayThroughput, BurstWhileTheGatewayIsStoppedCrossesWhole) {
  constexpr int kBurst = 1000, kDomain = 0;
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  ASSERT_TRUE(lcm.good());
  GatewayProcess gateway(kDomain, {"--dds-topic-prefix", "held_"});
  dds_entity_t pp = make_participant(kDomain, cyclone_config(), {});
  Qos q = stream_qos();
  Reader<hgdds_PartPose> reader(pp, &hgdds_PartPose_desc, "held_part_pose", q.get());
  ASSERT_TRUE(warm_up(lcm, reader));

  gateway.signal(SIGSTOP);
  ASSERT_TRUE(
      wait_until([&] { return process_state(gateway.pid()) == 'T'; }, [] { std::this_thread::sleep_for(5ms); }, 5s));
  hullgrind::part_pose_t m{};
  m.header.frame_id = "camera";
  m.num_parts = 1;
  for (int i = 0; i < kBurst; ++i) {
    m.header.seq = i;
    m.header.utime = hg::runtime::now_utime();
    ASSERT_EQ(lcm.publish("HG_PART_POSE", &m), 0);
  }
  const long long socket_drops = udp_receive_buffer_errors();
  gateway.signal(SIGCONT);

  wait_until([&] { return int(reader.samples.size()) >= kBurst; },
             [&] {
               if (reader.take() == 0) std::this_thread::sleep_for(10ms);
             },
             20s);
  std::this_thread::sleep_for(200ms);  // a duplicate would arrive right behind
  reader.take();
  std::vector<int> seen(kBurst, 0);
  int out_of_range = 0;
  for (const auto& o : reader.samples) {
    if (str(o->s.header.frame_id) == "warm-up") continue;
    if (o->s.header.seq < 0 || o->s.header.seq >= kBurst) ++out_of_range;
    else
      ++seen[o->s.header.seq];
  }
  int missing = 0, duplicated = 0;
  for (int n : seen) missing += n == 0, duplicated += n > 1;
  std::printf(
      "[ FIGURES  ] burst of %d while stopped: %zu received on DDS, %d missing, %d duplicated;"
      " kernel UDP receive-buffer drops %lld\n",
      kBurst, reader.samples.size(), missing, duplicated, socket_drops);
  EXPECT_EQ(socket_drops, 0) << "the burst did not fit the socket: the test cannot tell LCM's loss";
  EXPECT_EQ(missing, 0);
  EXPECT_EQ(duplicated, 0);
  EXPECT_EQ(out_of_range, 0);
  EXPECT_TRUE(gateway.running());
  dds_delete(pp);
}

}  // namespace
