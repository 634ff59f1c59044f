// The one TCP listener of the tree's HTTP / WebSocket servers (Boost.Beast: hg-station, hg-foxglove):
// binds (127.0.0.1 unless told otherwise), accepts on an Asio thread of its own, refuses connections over a
// limit, survives an exception of one connection's handler, and counts what clients got wrong. A server
// gives it what to do with each accepted socket; the protocol is the server's.
#pragma once

#include <utility>  // before Boost 1.74's asio, which uses std::exchange without it under C++20

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace hg::runtime {

struct ListenerOptions {
  std::string address = "127.0.0.1";
  int port = 0;                         // 0: any free port (tests; Listener::port() says which)
  std::string address_key = "address";  // the parameter that gave the address, named in its error
  int max_connections = 64;             // open connections; one more is closed at once (and counted)
};

// What clients got wrong, counted by the listener and by the servers' use of count_read_error.
struct ListenerStats {
  std::atomic<std::int64_t> bad_requests{0}, too_large{0}, timeouts{0}, refused_connections{0};
};

// How reading an HTTP request ended when it failed, counted in stats: the peer closed (not counted), the
// read's deadline passed, a body over its limit, a request that is not HTTP (or a header over its limit).
enum class ReadFailure { Closed, Timeout, TooLarge, Malformed };
ReadFailure count_read_error(const boost::beast::error_code& ec, ListenerStats& stats);

class Listener {
 public:
  // A connection's place in the count of open connections: a session holds one while it lives.
  class Held {
   public:
    explicit Held(Listener& l) : count_(l.connections_) { ++count_; }
    ~Held() { --count_; }
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;

   private:
    std::atomic<int>& count_;
  };
  using OnAccept = std::function<void(boost::asio::ip::tcp::socket)>;

  // Binds and listens: a bad address is std::invalid_argument naming options.address_key, a failure to
  // listen std::runtime_error naming the address and port.
  Listener(ListenerOptions options, ListenerStats& stats);
  ~Listener();  // stop()
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  boost::asio::io_context& io() { return io_; }
  int port() const { return port_; }
  int connections() const { return connections_.load(); }

  // Accepts on the listener's thread: each socket within max_connections goes to on_accept (on that
  // thread; the session it starts holds a Held). An exception out of a handler is logged, the loop goes on.
  void start(OnAccept on_accept);
  void stop();  // closes the acceptor, stops the loop, joins the thread

 private:
  void accept();

  ListenerOptions opt_;
  ListenerStats& stats_;
  std::atomic<int> connections_{0};  // before io_: the sessions its pending handlers hold release a Held
  boost::asio::io_context io_{1};
  boost::asio::ip::tcp::acceptor acceptor_{io_};
  OnAccept on_accept_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace hg::runtime
