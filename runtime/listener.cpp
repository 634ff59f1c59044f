#include "runtime/listener.hpp"

#include <boost/beast/http.hpp>

#include <stdexcept>

#include "runtime/log.hpp"

namespace hg::runtime {

namespace asio = boost::asio;
namespace beast = boost::beast;
using tcp = asio::ip::tcp;

ReadFailure count_read_error(const beast::error_code& ec, ListenerStats& stats) {
  namespace http = beast::http;
  if (ec == http::error::end_of_stream || ec == asio::error::eof) return ReadFailure::Closed;
  if (ec == beast::error::timeout) {
    ++stats.timeouts;
    return ReadFailure::Timeout;
  }
  if (ec == http::error::body_limit) {
    ++stats.too_large;
    return ReadFailure::TooLarge;
  }
  if (ec.category() == http::make_error_code(http::error::bad_target).category()) {
    ++stats.bad_requests;  // the parser's errors: not HTTP, a bad header, one over the header limit
    return ReadFailure::Malformed;
  }
  return ReadFailure::Closed;  // end of stream, reset: the peer went away
}

Listener::Listener(ListenerOptions options, ListenerStats& stats) : opt_(std::move(options)), stats_(stats) {
  beast::error_code ec;
  const auto address = asio::ip::make_address(opt_.address, ec);
  if (ec) throw std::invalid_argument(opt_.address_key + ": '" + opt_.address + "' is not an IP address");
  const tcp::endpoint ep(address, static_cast<unsigned short>(opt_.port));
  acceptor_.open(ep.protocol(), ec);
  if (!ec) acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(ep, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + opt_.address + ":" + std::to_string(opt_.port) + ": " +
                             ec.message());
  port_ = acceptor_.local_endpoint().port();
}

Listener::~Listener() { stop(); }

void Listener::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted) return;
    if (!ec && connections_ >= opt_.max_connections) {
      ++stats_.refused_connections;
      socket.close(ec);
    } else if (!ec) {
      on_accept_(std::move(socket));
    }
    accept();
  });
}

void Listener::start(OnAccept on_accept) {
  on_accept_ = std::move(on_accept);
  accept();
  thread_ = std::thread([this] {
    for (;;) {
      try {
        io_.run();
        return;
      } catch (const std::exception& e) {  // never let one connection's exception end the server
        logf(Level::Error, "server: %s", e.what());
      }
    }
  });
}

void Listener::stop() {
  if (!thread_.joinable()) return;
  asio::post(io_, [this] {
    beast::error_code ec;
    acceptor_.close(ec);
    io_.stop();
  });
  thread_.join();
}

}  // namespace hg::runtime
