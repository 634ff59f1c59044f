#include "station/server.hpp"

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <deque>
#include <optional>
#include <thread>

#include "runtime/log.hpp"

namespace hg::station {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using runtime::Level;
using runtime::logf;

namespace {

constexpr const char* kCsp =
    "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; connect-src 'self'; "
    "object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'";
constexpr std::size_t kWsQueueMessages = 512, kWsQueueBytes = 32u << 20;

template <class Message>
void security_headers(Message& m) {
  m.set(http::field::server, "hg-station");
  m.set("Content-Security-Policy", kCsp);
  m.set("X-Content-Type-Options", "nosniff");
  m.set("X-Frame-Options", "DENY");
  m.set("Referrer-Policy", "no-referrer");
  m.set(http::field::cache_control, "no-store");
}

// The WebSocket /api/live of one client: JSON events polled from LiveState, cloud frames on request.
template <class Stream>
class WsSession : public std::enable_shared_from_this<WsSession<Stream>> {
 public:
  WsSession(Stream&& stream, const LiveState& live, ServerStats& stats, Session who)
      : ws_(std::move(stream)), timer_(ws_.get_executor()), live_(live), stats_(stats), who_(std::move(who)) {}

  void run(http::request<http::string_body> req) {
    beast::get_lowest_layer(ws_).expires_never();
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(64 * 1024);
    ws_.async_accept(req, [self = this->shared_from_this()](beast::error_code ec) {
      if (ec) return self->close();
      ++self->stats_.websockets;
      self->seq_ = self->live_.last_event();
      Json hello = {{"type", "hello"}, {"user", self->who_.user}, {"role", role_name(self->who_.role)}};
      self->queue(false, std::make_shared<const std::string>(hello.dump()));
      self->read();
      self->poll();
    });
  }

 private:
  void close() {
    if (closed_) return;
    closed_ = true;
    timer_.cancel();
    beast::error_code ec;
    beast::get_lowest_layer(ws_).socket().close(ec);
  }

  void read() {
    ws_.async_read(in_, [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->on_message(beast::buffers_to_string(self->in_.data()));
      self->in_.consume(self->in_.size());
      self->read();
    });
  }

  void on_message(const std::string& text) {  // {"get": "cloud", "job": ID}
    Json m = Json::parse(text, nullptr, false);
    if (!m.is_object() || m.value("get", "") != "cloud") return;
    const Json job = m.value("job", Json(""));
    auto frame = live_.cloud_for(job.is_string() ? job.get<std::string>() : "");
    if (frame) queue(true, frame);
  }

  void poll() {
    if (closed_) return;
    std::vector<std::string> events;
    bool lost = false;
    seq_ = live_.events_since(seq_, events, lost);
    if (lost) queue(false, std::make_shared<const std::string>(R"({"type":"lost"})"));
    for (std::string& e : events) queue(false, std::make_shared<const std::string>(std::move(e)));
    timer_.expires_after(std::chrono::milliseconds(40));
    timer_.async_wait([self = this->shared_from_this()](beast::error_code ec) {
      if (!ec) self->poll();
    });
  }

  void queue(bool binary, std::shared_ptr<const std::string> data) {
    if (closed_) return;
    queued_bytes_ += data->size();
    out_.emplace_back(binary, std::move(data));
    if (out_.size() > kWsQueueMessages || queued_bytes_ > kWsQueueBytes) {  // a client that does not read
      ++stats_.websocket_drops;
      return close();
    }
    if (out_.size() == 1) write();
  }

  void write() {
    ws_.binary(out_.front().first);
    ws_.async_write(asio::buffer(*out_.front().second),
                    [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                      if (ec) return self->close();
                      self->queued_bytes_ -= self->out_.front().second->size();
                      self->out_.pop_front();
                      if (!self->out_.empty()) self->write();
                    });
  }

  websocket::stream<Stream> ws_;
  asio::steady_timer timer_;
  const LiveState& live_;
  ServerStats& stats_;
  Session who_;
  beast::flat_buffer in_;
  std::deque<std::pair<bool, std::shared_ptr<const std::string>>> out_;
  std::size_t queued_bytes_ = 0;
  std::uint64_t seq_ = 0;
  bool closed_ = false;

 public:
  ~WsSession() {
    if (stats_.websockets > 0) --stats_.websockets;
  }
};

}  // namespace

struct Server::Impl {
  ServerConfig config;
  Api& api;
  const LiveState& live;
  ServerStats stats;
  std::optional<asio::ssl::context> tls;
  runtime::Listener listener;

  Impl(ServerConfig c, Api& a, const LiveState& l)
      : config(std::move(c)),
        api(a),
        live(l),
        listener(runtime::ListenerOptions{config.address, config.port, "address", config.max_connections}, stats) {}
  void on_accept(tcp::socket socket);
};

namespace {

// One HTTP connection (plain or TLS): requests one after the other, each read with a deadline.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
 public:
  HttpSession(Stream&& stream, Server::Impl& server)
      : stream_(std::move(stream)), server_(server), held_(server.listener) {}

  void read(bool first) {
    parser_.emplace();
    parser_->body_limit(server_.config.max_body);
    parser_->header_limit(16 * 1024);
    auto& lowest = beast::get_lowest_layer(stream_);
    lowest.expires_after(first ? server_.config.read_timeout : server_.config.idle_timeout);
    http::async_read_header(
        stream_, buffer_, *parser_,
        [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

 private:
  void on_header(beast::error_code ec) {
    if (ec) return fail(ec);
    beast::get_lowest_layer(stream_).expires_after(server_.config.read_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = this->shared_from_this()](beast::error_code e, std::size_t) { self->on_read(e); });
  }

  void fail(beast::error_code ec) {
    switch (runtime::count_read_error(ec, server_.stats)) {
      case runtime::ReadFailure::TooLarge:
        return reply(json_error(413, "the body is over " + std::to_string(server_.config.max_body) + " bytes"), false);
      case runtime::ReadFailure::Malformed:
        return reply(json_error(400, "malformed HTTP request: " + ec.message()), false);
      default: return shutdown();
    }
  }

  void on_read(beast::error_code ec) {
    if (ec) return fail(ec);
    ++server_.stats.requests;
    auto req = parser_->release();
    HttpRequest r = to_request(req);
    if (websocket::is_upgrade(req)) return upgrade(std::move(req), r);
    HttpResponse res = server_.api.handle(r);
    if (res.status >= 400) ++server_.stats.bad_requests;
    reply(std::move(res), req.keep_alive(), req.method() == http::verb::head);
  }

  HttpRequest to_request(const http::request<http::string_body>& req) const {
    HttpRequest r;
    r.method = std::string(req.method_string());
    r.target = std::string(req.target());
    r.cookie = std::string(req[http::field::cookie]);
    r.csrf = std::string(req["X-CSRF-Token"]);
    r.content_type = std::string(req[http::field::content_type]);
    r.body = req.body();
    beast::error_code ec;
    auto ep = beast::get_lowest_layer(stream_).socket().remote_endpoint(ec);
    r.peer = ec ? "?" : ep.address().to_string();
    return r;
  }

  // /api/live with a valid session and a same-origin Origin (a page elsewhere cannot open it).
  void upgrade(http::request<http::string_body> req, const HttpRequest& r) {
    auto t = parse_target(r.target);
    auto who = server_.api.session_of(r);
    const std::string origin(req[http::field::origin]), host(req[http::field::host]);
    const bool same_origin = origin.empty() || origin == "http://" + host || origin == "https://" + host;
    if (!t || t->segments != std::vector<std::string>{"api", "live"})
      return reply(json_error(404, "no WebSocket here"), false);
    if (!who) return reply(json_error(401, "not logged in"), false);
    if (!same_origin) return reply(json_error(403, "WebSocket from another origin"), false);
    if (server_.stats.websockets >= server_.config.max_websockets)
      return reply(json_error(503, "too many live clients"), false);
    std::make_shared<WsSession<Stream>>(std::move(stream_), server_.live, server_.stats, *who)->run(std::move(req));
  }

  void reply(HttpResponse res, bool keep_alive, bool head = false) {
    keep_alive_ = keep_alive;
    if (!res.file.empty()) {
      http::response<http::file_body> m{http::status(res.status), 11};
      beast::error_code ec;
      m.body().open(res.file.c_str(), beast::file_mode::scan, ec);
      if (!ec) {
        m.set(http::field::content_type, res.content_type);
        finish(std::move(m), res, head);
        return;
      }
      res = json_error(404, "not found");
    }
    http::response<http::string_body> m{http::status(res.status), 11};
    m.set(http::field::content_type, res.content_type);
    m.body() = std::move(res.body);
    finish(std::move(m), res, head);
  }

  template <class Body>
  void finish(http::response<Body>&& m, const HttpResponse& res, bool head) {
    security_headers(m);
    for (const auto& [k, v] : res.headers) m.insert(k, v);
    m.keep_alive(keep_alive_);
    m.prepare_payload();
    auto sp = std::make_shared<http::response<Body>>(std::move(m));
    if (head) sp->body() = {};
    beast::get_lowest_layer(stream_).expires_after(server_.config.read_timeout);
    http::async_write(stream_, *sp, [self = this->shared_from_this(), sp](beast::error_code ec, std::size_t) {
      if (ec || !self->keep_alive_) return self->shutdown();
      self->read(false);
    });
  }

  void shutdown() {
    beast::error_code ec;
    beast::get_lowest_layer(stream_).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(stream_).socket().close(ec);
  }

  Stream stream_;
  Server::Impl& server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  bool keep_alive_ = false;
  runtime::Listener::Held held_;
};

}  // namespace

void Server::Impl::on_accept(tcp::socket socket) {
  if (!tls) {
    std::make_shared<HttpSession<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), *this)->read(true);
    return;
  }
  auto stream = std::make_shared<beast::ssl_stream<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), *tls);
  beast::get_lowest_layer(*stream).expires_after(config.read_timeout);
  stream->async_handshake(asio::ssl::stream_base::server, [this, stream](beast::error_code ec) {
    if (ec) {
      ++stats.bad_requests;
      return;
    }
    std::make_shared<HttpSession<beast::ssl_stream<beast::tcp_stream>>>(std::move(*stream), *this)->read(true);
  });
}

Server::Server(ServerConfig config, Api& api, const LiveState& live)
    : impl_(std::make_unique<Impl>(std::move(config), api, live)) {
  auto& c = impl_->config;
  if (c.tls_cert.empty() != c.tls_key.empty())
    throw std::invalid_argument("tls-cert and tls-key: give both or neither");
  if (!c.tls_cert.empty()) {
    impl_->tls.emplace(asio::ssl::context::tls_server);
    impl_->tls->set_options(asio::ssl::context::no_sslv2 | asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                            asio::ssl::context::no_tlsv1_1);
    impl_->tls->use_certificate_chain_file(c.tls_cert);
    impl_->tls->use_private_key_file(c.tls_key, asio::ssl::context::pem);
  }
}

Server::~Server() { stop(); }

void Server::start() {
  impl_->listener.start([impl = impl_.get()](tcp::socket socket) { impl->on_accept(std::move(socket)); });
}

void Server::stop() { impl_->listener.stop(); }

int Server::port() const { return impl_->listener.port(); }
const ServerStats& Server::stats() const { return impl_->stats; }

}  // namespace hg::station
