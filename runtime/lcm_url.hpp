// The LCM URL every hullgrind program uses (header-only, so tools that do not link hg_runtime share it).
#pragma once

#include <cstdlib>
#include <string>

namespace hg::runtime {

// Multicast with ttl=0: nothing leaves the machine.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

// LCM_DEFAULT_URL if set, else kDefaultLcmUrl.
inline std::string default_lcm_url() {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  return env && *env ? env : kDefaultLcmUrl;
}

// Plate clouds are megabytes: the kernel's default UDP receive buffer (~200 KB) loses the fragments of a
// burst of them. Asks for 4 MiB on udpm URLs that do not say otherwise (the kernel caps it at
// net.core.rmem_max).
inline std::string with_receive_buffer(std::string url) {
  if (url.rfind("udpm://", 0) == 0 && url.find("recv_buf_size") == std::string::npos)
    url += std::string(url.find('?') == std::string::npos ? "?" : "&") + "recv_buf_size=4194304";
  return url;
}

}  // namespace hg::runtime
