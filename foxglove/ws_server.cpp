#include "ws_server.hpp"

#include <utility>  // before Boost 1.74's asio, which uses std::exchange without it under C++20

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <deque>
#include <map>
#include <set>
#include <stdexcept>

namespace hg::foxglove {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using nlohmann::json;

namespace {

const char* kSubprotocols[] = {"foxglove.websocket.v1", "foxglove.sdk.v1"};

// The first subprotocol the client offers that we speak, or "".
std::string choose_subprotocol(std::string_view offered) {
  std::set<std::string> names;
  std::size_t start = 0;
  while (start <= offered.size()) {
    std::size_t end = offered.find(',', start);
    if (end == std::string_view::npos) end = offered.size();
    std::string_view t = offered.substr(start, end - start);
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
    while (!t.empty() && (t.back() == ' ' || t.back() == '\t')) t.remove_suffix(1);
    names.insert(std::string(t));
    start = end + 1;
  }
  for (const char* p : kSubprotocols)
    if (names.count(p)) return p;
  return "";
}

json channel_json(const WsChannel& c) {
  json j{
      {"id", c.id}, {"topic", c.topic}, {"encoding", c.encoding}, {"schemaName", c.schema_name}, {"schema", c.schema}};
  if (!c.schema_encoding.empty()) j["schemaEncoding"] = c.schema_encoding;
  return j;
}

std::string status_json(int level, const std::string& message) {
  return json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
}

}  // namespace

struct Session;

struct WsServer::Impl {
  WsServerOptions opt;
  net::io_context ioc;  // first: destroyed last, after the sessions its handlers hold
  tcp::acceptor acceptor{ioc};
  std::map<int, WsChannel> channels;  // io thread
  std::map<int, std::pair<std::uint64_t, std::shared_ptr<const std::string>>> last;
  std::uint64_t session_id = 0;

  mutable std::mutex mu;  // what other threads read
  std::vector<std::shared_ptr<Session>> sessions;
  std::map<int, int> subscribers;  // channel -> clients subscribed
  std::atomic<std::uint64_t> garbage{0}, refused{0};

  void accept();
  void subscribers_changed(int channel, int delta) {
    std::lock_guard<std::mutex> lock(mu);
    if ((subscribers[channel] += delta) <= 0) subscribers.erase(channel);
  }
  void remove(const Session* s);
};

struct Session : std::enable_shared_from_this<Session> {
  struct Item {
    bool text;
    std::string head;  // the text, or the binary header
    std::shared_ptr<const std::string> body;
  };

  WsServer::Impl& srv;
  websocket::stream<beast::tcp_stream> ws;
  beast::flat_buffer buf;
  std::optional<http::request_parser<http::string_body>> parser;
  std::string peer;
  bool open = false, closing = false, writing = false, ended = false;
  std::map<std::uint32_t, int> subs;  // subscription id -> channel
  std::map<int, std::uint32_t> by_channel;
  std::deque<Item> queue;
  std::size_t queued_bytes = 0, queued_binary = 0;
  std::atomic<std::uint64_t> sent{0}, dropped{0};
  std::atomic<std::size_t> subscription_count{0};

  Session(WsServer::Impl& s, tcp::socket sock) : srv(s), ws(std::move(sock)) {
    beast::error_code ec;
    auto ep = beast::get_lowest_layer(ws).socket().remote_endpoint(ec);
    peer = ec ? "?" : ep.address().to_string() + ":" + std::to_string(ep.port());
  }

  void start() {
    parser.emplace();
    parser->header_limit(16 * 1024);
    parser->body_limit(4096);
    beast::get_lowest_layer(ws).expires_after(std::chrono::seconds(10));
    http::async_read(beast::get_lowest_layer(ws), buf, *parser,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_request(ec); });
  }

  void refuse(http::status status, const std::string& why) {
    ++srv.refused;
    auto res = std::make_shared<http::response<http::string_body>>(status, 11);
    res->set(http::field::server, srv.opt.name);
    res->set(http::field::content_type, "text/plain");
    res->body() = why + "\n";
    res->prepare_payload();
    http::async_write(beast::get_lowest_layer(ws), *res,
                      [self = shared_from_this(), res](beast::error_code, std::size_t) {
                        beast::error_code ec;
                        beast::get_lowest_layer(self->ws).socket().shutdown(tcp::socket::shutdown_both, ec);
                        self->end();
                      });
  }

  void on_request(beast::error_code ec) {
    if (ec) return end();
    http::request<http::string_body> req = parser->release();
    if (!websocket::is_upgrade(req))
      return refuse(http::status::bad_request,
                    srv.opt.name + ": a Foxglove WebSocket server: open ws://HOST:PORT in Foxglove or Lichtblick");
    std::string proto = choose_subprotocol(std::string(req[http::field::sec_websocket_protocol]));
    if (proto.empty())
      return refuse(http::status::bad_request, "subprotocol foxglove.websocket.v1 (or foxglove.sdk.v1) required");
    {
      std::lock_guard<std::mutex> lock(srv.mu);
      if (srv.sessions.size() > srv.opt.max_clients)  // this one is already in the list
        return refuse(http::status::service_unavailable, "too many clients");
    }
    beast::get_lowest_layer(ws).expires_never();
    ws.set_option(websocket::stream_base::timeout{std::chrono::seconds(10), std::chrono::seconds(60), true});
    ws.set_option(websocket::stream_base::decorator([proto, name = srv.opt.name](websocket::response_type& res) {
      res.set(http::field::sec_websocket_protocol, proto);
      res.set(http::field::server, name);
    }));
    ws.read_message_max(srv.opt.max_client_message);
    ws.async_accept(req, [self = shared_from_this()](beast::error_code e) { self->on_accept(e); });
  }

  void on_accept(beast::error_code ec) {
    if (ec) return end();
    open = true;
    send_text(json{{"op", "serverInfo"},
                   {"name", srv.opt.name},
                   {"capabilities", json::array()},
                   {"supportedEncodings", json::array()},
                   {"metadata", json::object()},
                   {"sessionId", std::to_string(srv.session_id)}}
                  .dump());
    json list = json::array();
    for (const auto& [id, c] : srv.channels) list.push_back(channel_json(c));
    if (!list.empty()) send_text(json{{"op", "advertise"}, {"channels", list}}.dump());
    read();
  }

  void read() {
    ws.async_read(buf, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec == websocket::error::buffer_overflow) ++srv.garbage;  // Beast closes with "message too big"
    if (ec) return end();
    if (!ws.got_text()) return garbage("binary messages are not accepted: this server is read-only");
    std::string text = beast::buffers_to_string(buf.data());
    buf.consume(buf.size());
    json msg = json::parse(text, nullptr, false);
    if (msg.is_discarded() || !msg.is_object() || !msg.contains("op") || !msg["op"].is_string())
      return garbage("not a JSON object with an \"op\"");
    std::string why = handle(msg);
    if (!why.empty()) return garbage(why);
    if (!closing) read();
  }

  // One client operation; returns why it is not the protocol ("" when it is).
  std::string handle(const json& msg) {
    const std::string op = msg["op"];
    if (op == "subscribe") return subscribe(msg);
    if (op == "unsubscribe") return unsubscribe(msg);
    static const std::set<std::string> unsupported = {"advertise",
                                                      "unadvertise",
                                                      "getParameters",
                                                      "setParameters",
                                                      "subscribeParameterUpdates",
                                                      "unsubscribeParameterUpdates",
                                                      "callService",
                                                      "subscribeConnectionGraph",
                                                      "unsubscribeConnectionGraph",
                                                      "fetchAsset"};
    if (unsupported.count(op)) {
      send_text(status_json(2, "'" + op + "' is not offered: this server is read-only (see serverInfo capabilities)"));
      return "";
    }
    return "unknown op '" + op.substr(0, 40) + "'";
  }

  std::string subscribe(const json& msg) {
    if (!msg.contains("subscriptions") || !msg["subscriptions"].is_array()) return "subscribe without subscriptions[]";
    for (const json& s : msg["subscriptions"]) {
      if (!s.is_object() || !s.contains("id") || !s.contains("channelId") || !s["id"].is_number_unsigned() ||
          !s["channelId"].is_number_integer() || s["id"].get<std::uint64_t>() > 0xFFFFFFFFu)
        return "subscribe: each subscription needs an unsigned 32-bit id and a channelId";
      auto id = s["id"].get<std::uint32_t>();
      int channel = s["channelId"].get<int>();
      if (subs.count(id)) return "subscribe: subscription id " + std::to_string(id) + " is in use";
      if (!srv.channels.count(channel)) {
        send_text(status_json(1, "channel " + std::to_string(channel) + " is not advertised"));
        continue;
      }
      if (by_channel.count(channel)) {
        send_text(status_json(1, "channel " + std::to_string(channel) + " is already subscribed"));
        continue;
      }
      subs[id] = channel;
      by_channel[channel] = id;
      srv.subscribers_changed(channel, +1);
      auto last = srv.last.find(channel);
      if (last != srv.last.end()) send_message(channel, last->second.first, last->second.second);
    }
    subscription_count = subs.size();
    return "";
  }

  std::string unsubscribe(const json& msg) {
    if (!msg.contains("subscriptionIds") || !msg["subscriptionIds"].is_array())
      return "unsubscribe without subscriptionIds[]";
    for (const json& s : msg["subscriptionIds"]) {
      if (!s.is_number_unsigned()) return "unsubscribe: subscription ids are unsigned integers";
      auto it = subs.find(s.get<std::uint32_t>());
      if (it == subs.end()) continue;
      drop_subscription(it->second);
    }
    return "";
  }

  void drop_subscription(int channel) {
    auto it = by_channel.find(channel);
    if (it == by_channel.end()) return;
    subs.erase(it->second);
    by_channel.erase(it);
    srv.subscribers_changed(channel, -1);
    subscription_count = subs.size();
  }

  void garbage(const std::string& why) {
    ++srv.garbage;
    closing = true;
    queue.clear();  // nothing more for it; a write in flight finishes first
    queued_bytes = queued_binary = 0;
    close_reason = why.substr(0, 120);  // a close frame's reason is at most 123 bytes
    if (!writing) do_close();
  }
  std::string close_reason;
  void do_close() {
    ws.async_close(websocket::close_reason(websocket::close_code::policy_error, close_reason),
                   [self = shared_from_this()](beast::error_code) { self->end(); });
  }

  void send_text(std::string text) {
    if (!open || closing) return;
    queued_bytes += text.size();
    queue.push_back(Item{true, std::move(text), nullptr});
    write_next();
  }

  void send_message(int channel, std::uint64_t ts, const std::shared_ptr<const std::string>& body) {
    auto it = by_channel.find(channel);
    if (!open || closing || it == by_channel.end()) return;
    if (queued_binary >= srv.opt.queue_frames || queued_bytes + body->size() > srv.opt.queue_bytes) {
      ++dropped;  // the client is slower than the bus: it misses this one, nobody waits
      return;
    }
    std::string head(13, '\0');
    head[0] = 1;  // Message Data
    for (int i = 0; i < 4; ++i) head[1 + i] = static_cast<char>((it->second >> (8 * i)) & 0xFF);
    for (int i = 0; i < 8; ++i) head[5 + i] = static_cast<char>((ts >> (8 * i)) & 0xFF);
    queued_bytes += body->size() + head.size();
    ++queued_binary;
    queue.push_back(Item{false, std::move(head), body});
    write_next();
  }

  void write_next() {
    if (writing || queue.empty()) return;
    writing = true;
    const Item& item = queue.front();
    auto done = [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_write(ec); };
    ws.text(item.text);
    if (item.text) {
      ws.async_write(net::buffer(item.head), done);
    } else {
      std::array<net::const_buffer, 2> b{net::buffer(item.head), net::buffer(*item.body)};
      ws.async_write(b, done);
    }
  }

  void on_write(beast::error_code ec) {
    writing = false;
    if (ec) return end();
    if (!queue.empty()) {  // empty when garbage() cleared it meanwhile
      const Item& item = queue.front();
      queued_bytes -= item.head.size() + (item.body ? item.body->size() : 0);
      if (!item.text) --queued_binary, ++sent;
      queue.pop_front();
    }
    if (closing) return do_close();
    write_next();
  }

  void end() {
    if (ended) return;
    ended = true;
    open = false;
    for (const auto& [channel, id] : by_channel) srv.subscribers_changed(channel, -1);
    by_channel.clear();
    subs.clear();
    srv.remove(this);
  }
};

void WsServer::Impl::remove(const Session* s) {
  std::lock_guard<std::mutex> lock(mu);
  for (auto it = sessions.begin(); it != sessions.end(); ++it)
    if (it->get() == s) {
      sessions.erase(it);  // the handler running holds the last reference
      return;
    }
}

void WsServer::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket sock) {
    if (ec) {
      if (ec != net::error::operation_aborted) accept();
      return;
    }
    auto s = std::make_shared<Session>(*this, std::move(sock));
    {
      std::lock_guard<std::mutex> lock(mu);
      sessions.push_back(s);
    }
    s->start();
    accept();
  });
}

WsServer::WsServer(WsServerOptions options) : impl_(std::make_shared<Impl>()) {
  impl_->opt = std::move(options);
  impl_->session_id = static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  beast::error_code ec;
  tcp::endpoint ep(net::ip::make_address(impl_->opt.host, ec), static_cast<unsigned short>(impl_->opt.port));
  if (ec) throw std::invalid_argument("host '" + impl_->opt.host + "' is not an IP address (--host)");
  auto& a = impl_->acceptor;
  a.open(ep.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(ep, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + impl_->opt.host + ":" + std::to_string(impl_->opt.port) + ": " +
                             ec.message());
  port_ = a.local_endpoint().port();
  impl_->accept();
  thread_ = std::thread([impl = impl_] { impl->ioc.run(); });
}

WsServer::~WsServer() {
  impl_->ioc.stop();
  thread_.join();
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->sessions.clear();
}

void WsServer::advertise(std::vector<WsChannel> channels) {
  net::post(impl_->ioc, [impl = impl_, channels = std::move(channels)] {
    json list = json::array();
    for (const WsChannel& c : channels) {
      impl->channels[c.id] = c;
      list.push_back(channel_json(c));
    }
    std::string text = json{{"op", "advertise"}, {"channels", list}}.dump();
    std::lock_guard<std::mutex> lock(impl->mu);
    for (auto& s : impl->sessions) s->send_text(text);
  });
}

void WsServer::unadvertise(const std::vector<int>& ids) {
  net::post(impl_->ioc, [impl = impl_, ids] {
    for (int id : ids) impl->channels.erase(id), impl->last.erase(id);
    std::string text = json{{"op", "unadvertise"}, {"channelIds", ids}}.dump();
    std::vector<std::shared_ptr<Session>> list;
    {
      std::lock_guard<std::mutex> lock(impl->mu);
      list = impl->sessions;
    }
    for (auto& s : list) {
      for (int id : ids) s->drop_subscription(id);
      s->send_text(text);
    }
  });
}

void WsServer::publish(int channel, std::uint64_t ts, std::shared_ptr<const std::string> payload) {
  net::post(impl_->ioc, [impl = impl_, channel, ts, payload = std::move(payload)] {
    if (!impl->channels.count(channel)) return;
    impl->last[channel] = {ts, payload};
    std::vector<std::shared_ptr<Session>> list;
    {
      std::lock_guard<std::mutex> lock(impl->mu);
      list = impl->sessions;
    }
    for (auto& s : list) s->send_message(channel, ts, payload);
  });
}

bool WsServer::subscribed(int channel) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->subscribers.count(channel) > 0;
}

WsStats WsServer::stats() const {
  WsStats st;
  std::lock_guard<std::mutex> lock(impl_->mu);
  for (const auto& s : impl_->sessions)
    st.clients.push_back(WsClientStats{s->peer, s->sent.load(), s->dropped.load(), s->subscription_count.load()});
  st.disconnected_garbage = impl_->garbage.load();
  st.refused = impl_->refused.load();
  return st;
}

}  // namespace hg::foxglove
