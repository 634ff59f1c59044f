// The station's HTTP and WebSocket server: Boost.Beast on one Asio thread of its own (the LCM loop runs on
// the process's main thread), optional TLS (OpenSSL through Boost.Asio). Every read has a deadline, bodies
// over max_body are answered 413, malformed requests 400, then the connection closes; the number of
// connections and the WebSocket's send queue are bounded, so one bad client cannot take the station down.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "runtime/listener.hpp"
#include "station/api.hpp"
#include "station/live.hpp"

namespace hg::station {

struct ServerConfig {
  std::string address = "127.0.0.1";
  int port = 8080;                // 0: any free port (tests; see Server::port())
  std::string tls_cert, tls_key;  // both or neither (PEM files)
  std::size_t max_body = 1 << 20;
  std::chrono::milliseconds read_timeout{10000};  // a whole request (headers and body) must arrive in this
  std::chrono::milliseconds idle_timeout{30000};  // keep-alive: the next request must start in this
  int max_connections = 64;
  int max_websockets = 16;
};

// bad_requests, too_large, timeouts, refused_connections: runtime::ListenerStats.
struct ServerStats : runtime::ListenerStats {
  std::atomic<std::int64_t> requests{0}, websockets{0}, websocket_drops{0};
};

class Server {
 public:
  // Binds and listens (throws std::runtime_error naming the address on failure); serves after start().
  Server(ServerConfig config, Api& api, const LiveState& live);
  ~Server();
  void start();  // the server thread
  void stop();   // joins it
  int port() const;
  const ServerStats& stats() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace hg::station
