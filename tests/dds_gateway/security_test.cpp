// hg-dds-gateway with DDS Security (a set made by tools/make-dds-security.sh), in a private network
// namespace. Four plant-side participants, each its own process (tests/dds_gateway/dds_peer.cpp), try for
// a while to read the outline topic and to send a job request:
//   plant     trusted identity, permitted to read everything and write job requests (the control: it must
//             succeed, or the negative results below would prove nothing);
//   observer  trusted identity whose permissions allow reading health only;
//   anonymous no DDS Security at all;
//   rogue     identity and permissions from a CA the gateway does not trust.
// Meanwhile a packet socket on lo records every UDP payload: the outline's text must never appear in the
// DDS traffic in clear (it does in LCM's, which shows the capture works).
#include <arpa/inet.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <netinet/ip.h>
#include <netinet/udp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "helpers.hpp"
#include "hullgrind/heartbeat_t.hpp"
#include "hullgrind/job_request_t.hpp"
#include "hullgrind/outline_t.hpp"

using namespace hgtest;
using namespace hg::dds_gateway;

namespace {

constexpr int kDomain = 0;
const std::string kMarker = "OUTLINE-SECRET-5b1e9c";

struct PeerResult {
  std::string output;
  bool reader_ok = false, writer_ok = false;
  int outline_samples = -1, job_writes = -1;
};

PeerResult parse(const std::string& out) {
  PeerResult r;
  r.output = out;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line == "reader ok") r.reader_ok = true;
    if (line == "writer ok") r.writer_ok = true;
    if (line.rfind("outline_samples ", 0) == 0) r.outline_samples = std::stoi(line.substr(16));
    if (line.rfind("job_writes ", 0) == 0) r.job_writes = std::stoi(line.substr(11));
  }
  return r;
}

// A dds_peer process and the read end of its stdout.
struct Peer {
  hg::test::ChildProcess process;
  int fd = -1;
};

Peer start_peer(const std::string& job_id, double seconds, const std::string& sec_dir, const std::string& identity) {
  int p[2];
  if (pipe(p) != 0) return {};
  std::vector<std::string> args = {std::string(HG_TESTS_DIR) + "/dds_peer",
                                   std::to_string(kDomain),
                                   cyclone_config(),
                                   "hg_",
                                   job_id,
                                   std::to_string(seconds)};
  if (!sec_dir.empty()) {
    args.push_back(sec_dir);
    args.push_back(identity);
  }
  Peer peer{hg::test::ChildProcess(args, hg::test::ChildOptions().stdout_to_fd(p[1])), p[0]};
  close(p[1]);
  return peer;
}

// Everything the peer printed, once it has closed its stdout; it is reaped (killed after 60 s more).
std::string finish_peer(Peer& peer) {
  std::string out;
  char buf[512];
  ssize_t n;
  while ((n = read(peer.fd, buf, sizeof buf)) > 0) out.append(buf, std::size_t(n));
  close(peer.fd);
  if (!peer.process.wait(60s)) peer.process.kill_now();
  return out;
}

// Every UDP payload seen on lo, by destination port.
class Sniffer {
 public:
  Sniffer() {
    fd_ = socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK, htons(ETH_P_ALL));
    if (fd_ < 0) return;
    sockaddr_ll sll{};
    sll.sll_family = AF_PACKET;
    sll.sll_protocol = htons(ETH_P_ALL);
    sll.sll_ifindex = int(if_nametoindex("lo"));
    if (bind(fd_, reinterpret_cast<sockaddr*>(&sll), sizeof sll) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~Sniffer() {
    if (fd_ >= 0) close(fd_);
  }
  bool good() const { return fd_ >= 0; }
  void drain() {
    unsigned char buf[70000];
    for (;;) {
      ssize_t n = recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) return;
      if (n < 14 + 20 + 8) continue;
      const unsigned char* ip = buf + 14;  // lo frames carry a zeroed Ethernet header
      if ((ip[0] >> 4) != 4 || ip[9] != IPPROTO_UDP) continue;
      std::size_t ihl = std::size_t(ip[0] & 0x0f) * 4;
      if (std::size_t(n) < 14 + ihl + 8) continue;
      const unsigned char* udp = ip + ihl;
      int dport = (udp[2] << 8) | udp[3];
      payloads.emplace_back(dport, std::string(reinterpret_cast<const char*>(udp + 8), std::size_t(n) - 14 - ihl - 8));
    }
  }
  std::vector<std::pair<int, std::string>> payloads;

 private:
  int fd_ = -1;
};

TEST(DdsGatewaySecurity, OnlyPermittedParticipantsReadOutlinesOrInjectJobs) {
  // A fresh security set from the project's script.
  char tmpl[] = "/tmp/hg-dds-sec-XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl;
  std::string cmd = std::string(HG_SOURCE_DIR) + "/tools/make-dds-security.sh --force " + dir + " >/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  ASSERT_TRUE(lcm.good());
  Collector<hullgrind::job_request_t> requests(lcm, "HG_JOB_REQUEST");
  Collector<hullgrind::heartbeat_t> beats(lcm, "HG_HEARTBEAT");
  Sniffer sniffer;
  ASSERT_TRUE(sniffer.good()) << "no packet socket on lo (needs CAP_NET_RAW in the test's namespace)";

  GatewayProcess gateway(kDomain,
                         {"--dds-security-identity-ca", dir + "/identity_ca.pem", "--dds-security-identity-cert",
                          dir + "/gateway.pem", "--dds-security-private-key", dir + "/gateway.key",
                          "--dds-security-permissions-ca", dir + "/permissions_ca.pem", "--dds-security-governance",
                          dir + "/governance.p7s", "--dds-security-permissions", dir + "/gateway_permissions.p7s"});
  auto pump = [&] {
    lcm.handleTimeout(5);
    sniffer.drain();
  };
  auto gateway_beat = [&]() -> const hullgrind::heartbeat_t* {
    for (auto it = beats.msgs.rbegin(); it != beats.msgs.rend(); ++it)
      if (it->pid == gateway.pid()) return &*it;
    return nullptr;
  };
  ASSERT_TRUE(wait_until([&] { return gateway_beat() != nullptr; }, pump, 20s)) << "the secured gateway did not start";
  EXPECT_EQ(gateway_beat()->state, +hullgrind::heartbeat_t::STATE_OK) << gateway_beat()->state_text;

  hullgrind::outline_t outline{};
  outline.header.frame_id = "camera";
  outline.error_text = kMarker;
  outline.status = hullgrind::outline_t::STATUS_NO_LOOP;
  lcm.publish("HG_OUTLINE", &outline);  // held by the gateway for late joiners

  constexpr double kSeconds = 8;
  Peer plant = start_peer("plant-job", kSeconds, dir, "plant");
  Peer observer = start_peer("observer-job", kSeconds, dir, "observer");
  Peer anonymous = start_peer("anonymous-job", kSeconds, "", "");
  Peer rogue = start_peer("rogue-job", kSeconds, dir + "/rogue", "plant");
  // Live outlines too, not only the stored one.
  auto end = Clock::now() + std::chrono::duration<double>(kSeconds + 1);
  auto next = Clock::now();
  while (Clock::now() < end) {
    if (Clock::now() >= next) {
      ++outline.header.seq;
      lcm.publish("HG_OUTLINE", &outline);
      next += 250ms;
    }
    pump();
  }
  PeerResult r_plant = parse(finish_peer(plant)), r_observer = parse(finish_peer(observer)),
             r_anonymous = parse(finish_peer(anonymous)), r_rogue = parse(finish_peer(rogue));
  wait_until([] { return false; }, pump, 500ms);

  for (auto* r : {&r_plant, &r_observer, &r_anonymous, &r_rogue}) std::printf("[ PEER     ] %s", r->output.c_str());
  std::map<std::string, int> jobs;
  for (auto& m : requests.msgs) ++jobs[m.job_id];

  // The control: a permitted participant reads outlines and its job reaches LCM.
  EXPECT_TRUE(r_plant.reader_ok && r_plant.writer_ok) << r_plant.output;
  EXPECT_GT(r_plant.outline_samples, 0) << r_plant.output;
  EXPECT_GT(jobs["plant-job"], 0) << "the permitted plant participant's job did not reach LCM";

  // Trusted identity without the permission: its own side already refuses to make the entities.
  EXPECT_FALSE(r_observer.reader_ok) << r_observer.output;
  EXPECT_FALSE(r_observer.writer_ok) << r_observer.output;
  EXPECT_EQ(r_observer.outline_samples, 0) << r_observer.output;
  EXPECT_EQ(jobs["observer-job"], 0);

  // No security, or an untrusted CA: it may make entities and write, but the gateway never matches it.
  EXPECT_TRUE(r_anonymous.reader_ok && r_anonymous.writer_ok) << r_anonymous.output;
  EXPECT_GT(r_anonymous.job_writes, 0) << r_anonymous.output;
  EXPECT_EQ(r_anonymous.outline_samples, 0) << r_anonymous.output;
  EXPECT_EQ(jobs["anonymous-job"], 0);
  EXPECT_EQ(r_rogue.outline_samples, 0) << r_rogue.output;
  EXPECT_EQ(jobs["rogue-job"], 0);
  for (auto& [id, n] : jobs) EXPECT_TRUE(n == 0 || id == "plant-job") << id << " reached LCM";

  // Encryption: the outline's text is in LCM's packets (port 7667) but never in DDS's.
  int lcm_hits = 0, dds_hits = 0, dds_packets = 0, dds_job_id_hits = 0;
  for (auto& [port, payload] : sniffer.payloads) {
    bool hit = payload.find(kMarker) != std::string::npos;
    if (port == 7667) {
      lcm_hits += hit;
    } else {
      ++dds_packets;
      dds_hits += hit;
      dds_job_id_hits += payload.find("plant-job") != std::string::npos;
    }
  }
  std::printf("[ FIGURES  ] captured %zu UDP payloads on lo: %d DDS, marker in %d LCM / %d DDS, plant-job in %d DDS\n",
              sniffer.payloads.size(), dds_packets, lcm_hits, dds_hits, dds_job_id_hits);
  EXPECT_GT(lcm_hits, 0) << "the capture saw no LCM outline: it proves nothing";
  EXPECT_GT(dds_packets, 0);
  EXPECT_EQ(dds_hits, 0) << "outline text crossed DDS in clear";
  EXPECT_EQ(dds_job_id_hits, 0) << "a job request crossed DDS in clear";
  EXPECT_TRUE(gateway.running());
  std::system(("rm -rf " + dir).c_str());
}

// The control of the encryption check above: without DDS Security the same capture does find the
// outline's text in DDS packets, so its absence there means encryption, not a blind capture.
TEST(DdsGatewaySecurity, WithoutSecurityTheCaptureSeesOutlinesInClear) {
  lcm::LCM lcm{hg::runtime::default_lcm_url()};
  ASSERT_TRUE(lcm.good());
  Sniffer sniffer;
  ASSERT_TRUE(sniffer.good());
  GatewayProcess gateway(kDomain);
  hullgrind::outline_t outline{};
  outline.error_text = kMarker;
  constexpr double kSeconds = 4;
  Peer anonymous = start_peer("anonymous-job", kSeconds, "", "");
  auto end = Clock::now() + std::chrono::duration<double>(kSeconds + 1);
  auto next = Clock::now();
  while (Clock::now() < end) {
    if (Clock::now() >= next) {
      lcm.publish("HG_OUTLINE", &outline);
      next += 250ms;
    }
    lcm.handleTimeout(5);
    sniffer.drain();
  }
  PeerResult r = parse(finish_peer(anonymous));
  sniffer.drain();
  EXPECT_GT(r.outline_samples, 0) << r.output;
  int dds_hits = 0;
  for (auto& [port, payload] : sniffer.payloads)
    if (port != 7667) dds_hits += payload.find(kMarker) != std::string::npos;
  EXPECT_GT(dds_hits, 0) << "unsecured DDS traffic should carry the outline text in clear";
}

}  // namespace
