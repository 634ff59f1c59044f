#include "ws_server.hpp"

#include <utility>  // before Boost 1.74's asio, which uses std::exchange without it under C++20

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "runtime/listener.hpp"
#include "runtime/log.hpp"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
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
  runtime::ListenerStats requests;
  runtime::Listener listener;  // its io_context before the sessions: destroyed after them
  net::io_context& ioc;
  std::map<int, WsChannel> channels;  // io thread
  std::map<int, std::pair<std::uint64_t, std::shared_ptr<const std::string>>> last;
  std::uint64_t session_id = 0;

  mutable std::mutex mu;  // what other threads read
  std::vector<std::shared_ptr<Session>> sessions;
  std::map<int, int> subscribers;  // channel -> clients subscribed
  std::atomic<std::uint64_t> garbage{0}, refused{0};

  explicit Impl(WsServerOptions o)
      : opt(std::move(o)),
        listener(runtime::ListenerOptions{opt.host, opt.port, "host", opt.max_connections}, requests),
        ioc(listener.io()) {}
  void on_accept(tcp::socket sock);
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
  runtime::Listener::Held held;
  WsIdentity who;
  std::map<std::uint32_t, WsClientChannel> client_channels;

  Session(WsServer::Impl& s, tcp::socket sock) : srv(s), ws(std::move(sock)), held(s.listener) {
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
    if (ec && runtime::count_read_error(ec, srv.requests) == runtime::ReadFailure::Malformed)
      return refuse(http::status::bad_request, "malformed HTTP request: " + ec.message());
    if (ec) return end();
    http::request<http::string_body> req = parser->release();
    if (!websocket::is_upgrade(req))
      return refuse(http::status::bad_request,
                    srv.opt.name + ": a Foxglove WebSocket server: open ws://HOST:PORT in Foxglove or Lichtblick");
    std::string proto = choose_subprotocol(std::string(req[http::field::sec_websocket_protocol]));
    if (proto.empty())
      return refuse(http::status::bad_request, "subprotocol foxglove.websocket.v1 (or foxglove.sdk.v1) required");
    if (srv.opt.on_publish && srv.opt.identify) {
      who = srv.opt.identify(std::string(req[http::field::authorization]), peer.substr(0, peer.rfind(':')));
      if (!who.refusal.empty()) return refuse(http::status::unauthorized, who.refusal);
    }
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
    // One frame a message, written in one go: Beast's default cuts a message into 4 KB frames, each its own
    // write (800 for a 3 MB point cloud). Control frames wait for the message.
    ws.auto_fragment(false);
    ws.async_accept(req, [self = shared_from_this()](beast::error_code e) { self->on_accept(e); });
  }

  void on_accept(beast::error_code ec) {
    if (ec) return end();
    open = true;
    const bool publishing = bool(srv.opt.on_publish);
    send_text(json{{"op", "serverInfo"},
                   {"name", srv.opt.name},
                   {"capabilities", publishing ? json::array({"clientPublish"}) : json::array()},
                   {"supportedEncodings", publishing ? json::array({"json"}) : json::array()},
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
    if (!ws.got_text()) {
      std::string why = client_message();
      buf.consume(buf.size());
      if (!why.empty()) return garbage(why);
      return read();
    }
    std::string text = beast::buffers_to_string(buf.data());
    buf.consume(buf.size());
    json msg = json::parse(text, nullptr, false);
    if (msg.is_discarded() || !msg.is_object() || !msg.contains("op") || !msg["op"].is_string())
      return garbage("not a JSON object with an \"op\"");
    std::string why = handle(msg);
    if (!why.empty()) return garbage(why);
    if (!closing) read();
  }

  // A binary frame: clientPublish (opcode 1, channel id, payload) on a channel this client advertised;
  // returns why it is not the protocol ("" when it is). A refused message is answered with a status.
  std::string client_message() {
    if (!srv.opt.on_publish) return "binary messages are not accepted: this server is read-only";
    std::string data = beast::buffers_to_string(buf.data());
    if (data.size() < 5 || data[0] != 1) return "a binary message must be clientPublish (opcode 1)";
    std::uint32_t id = 0;
    for (int i = 0; i < 4; ++i) id |= std::uint32_t(std::uint8_t(data[1 + i])) << (8 * i);
    auto it = client_channels.find(id);
    if (it == client_channels.end()) return "clientPublish on channel " + std::to_string(id) + ", not advertised";
    std::string why = srv.opt.on_publish(it->second, who.user, std::string_view(data).substr(5));
    if (!why.empty()) send_text(status_json(2, why));
    return "";
  }

  std::string client_advertise(const json& msg) {
    if (!msg.contains("channels") || !msg["channels"].is_array()) return "advertise without channels[]";
    for (const json& c : msg["channels"]) {
      if (!c.is_object() || !c.contains("id") || !c["id"].is_number_unsigned() ||
          c["id"].get<std::uint64_t>() > 0xFFFFFFFFu || !c.contains("topic") || !c["topic"].is_string() ||
          !c.contains("encoding") || !c["encoding"].is_string())
        return "advertise: each channel needs an unsigned 32-bit id, a topic and an encoding";
      WsClientChannel ch{c["id"].get<std::uint32_t>(), c["topic"], c["encoding"], c.value("schemaName", "")};
      std::string refused;
      if (!who.may_publish)
        refused = "publishing needs an operator's login (HTTP Basic with a user of the station's users file)";
      else if (!srv.opt.publish_topics.count(ch.topic))
        refused = "'" + ch.topic.substr(0, 40) + "' may not be published (only HG_JOB_REQUEST)";
      else if (ch.encoding != "json")
        refused = "encoding '" + ch.encoding.substr(0, 20) + "': only json is accepted";
      if (!refused.empty()) {
        send_text(status_json(2, refused));
        continue;
      }
      client_channels[ch.id] = std::move(ch);
    }
    return "";
  }

  std::string client_unadvertise(const json& msg) {
    if (!msg.contains("channelIds") || !msg["channelIds"].is_array()) return "unadvertise without channelIds[]";
    for (const json& id : msg["channelIds"]) {
      if (!id.is_number_unsigned()) return "unadvertise: channel ids are unsigned integers";
      client_channels.erase(id.get<std::uint32_t>());
    }
    return "";
  }

  // One client operation; returns why it is not the protocol ("" when it is).
  std::string handle(const json& msg) {
    const std::string op = msg["op"];
    if (op == "subscribe") return subscribe(msg);
    if (op == "unsubscribe") return unsubscribe(msg);
    if (op == "advertise" && srv.opt.on_publish) return client_advertise(msg);
    if (op == "unadvertise" && srv.opt.on_publish) return client_unadvertise(msg);
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

void WsServer::Impl::on_accept(tcp::socket sock) {
  auto s = std::make_shared<Session>(*this, std::move(sock));
  {
    std::lock_guard<std::mutex> lock(mu);
    sessions.push_back(s);
  }
  s->start();
}

// Names the server's thread (top and /proc/PID/task/TID/comm show it) and raises its nice value to `nice`
// (Linux: per thread; an unprivileged thread may raise its own). Never lowers it: a process started at a
// higher one (the supervisor's nice) keeps the server there.
static void enter_server_thread(int nice) {
  pthread_setname_np(pthread_self(), "hg-fox-server");
  const auto tid = static_cast<id_t>(gettid());
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, tid);
  if (errno == 0 && nice > now && setpriority(PRIO_PROCESS, tid, nice) != 0)
    runtime::logf(runtime::Level::Warn, "cannot set the server thread's nice value to %d (%s)", nice,
                  std::strerror(errno));
}

WsServer::WsServer(WsServerOptions options) : impl_(std::make_shared<Impl>(std::move(options))) {
  impl_->session_id = static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  net::post(impl_->ioc, [nice = impl_->opt.thread_nice] { enter_server_thread(nice); });
  impl_->listener.start([impl = impl_.get()](tcp::socket sock) { impl->on_accept(std::move(sock)); });
}

WsServer::~WsServer() {
  impl_->listener.stop();
  std::lock_guard<std::mutex> lock(impl_->mu);
  impl_->sessions.clear();
}

int WsServer::bound_port() const { return impl_->listener.port(); }

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
  std::unique_lock<std::mutex> lock(impl_->mu);
  return stats_locked();
}

std::optional<WsStats> WsServer::try_stats() const {
  std::unique_lock<std::mutex> lock(impl_->mu, std::try_to_lock);
  if (!lock.owns_lock()) return std::nullopt;
  return stats_locked();
}

WsStats WsServer::stats_locked() const {
  WsStats st;
  for (const auto& s : impl_->sessions)
    st.clients.push_back(WsClientStats{s->peer, s->sent.load(), s->dropped.load(), s->subscription_count.load()});
  st.disconnected_garbage = impl_->garbage.load();
  st.refused = impl_->refused.load();
  st.bad_requests = impl_->requests.bad_requests.load();
  st.timeouts = impl_->requests.timeouts.load();
  st.refused_connections = impl_->requests.refused_connections.load();
  return st;
}

}  // namespace hg::foxglove
