// A Foxglove WebSocket protocol server (foxglove/ws-protocol docs/spec.md, subprotocol
// foxglove.websocket.v1; foxglove.sdk.v1, the name newer clients ask for, is accepted too) on Boost.Beast:
// serverInfo, advertise / unadvertise, subscribe / unsubscribe, binary message data, status. Read-only
// unless the caller gives on_publish: then the capability clientPublish, for the topics it names, for the
// clients whose identity (from their upgrade request) may publish. No parameters or services.
//
// It never slows its caller: publish() only hands a shared payload to the server's own thread. Each
// client has a bounded queue (frames and bytes); a message that does not fit is dropped for that client
// and counted. A client that sends something that is not the protocol (not JSON, unknown op, bad fields,
// binary data, oversized frames) is disconnected with a close reason.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace hg::foxglove {

struct WsChannel {
  int id;
  std::string topic, encoding, schema_name, schema, schema_encoding;
};

// Who a client is, from the Authorization header of its upgrade request.
struct WsIdentity {
  std::string user;          // "": anonymous
  bool may_publish = false;  // its advertisements of a publishable topic are accepted
  std::string refusal;       // not empty: the connection is refused (HTTP 401) with this text
};

// A channel a client advertised to publish on.
struct WsClientChannel {
  std::uint32_t id = 0;
  std::string topic, encoding, schema_name;
};

struct WsServerOptions {
  std::string host = "127.0.0.1";
  int port = 8765;  // 0: any free port (tests; bound_port() says which)
  std::string name = "hg-foxglove";
  std::size_t max_clients = 16;            // WebSocket clients; one more is answered HTTP 503
  int max_connections = 64;                // open TCP connections (clients and requests being read)
  std::size_t queue_frames = 256;          // per client
  std::size_t queue_bytes = 64u << 20;     // per client
  std::size_t max_client_message = 65536;  // a client's frame larger than this is garbage
  // The nice value of the server's thread (its writes to viewers): above the cell's 0, under load a viewer's
  // frames wait (and are dropped, counted) rather than the cell's processes. 0: the process's own.
  int thread_nice = 0;
  // Client publishing: off without on_publish. Both are called on the server's thread. identify gets the
  // upgrade request's Authorization header ("" if none) and the peer's address.
  std::function<WsIdentity(const std::string& authorization, const std::string& peer)> identify;
  std::set<std::string> publish_topics;  // the only topics a client may advertise
  // A message a client published on a channel it advertised; returns why it was refused ("": published).
  std::function<std::string(const WsClientChannel&, const std::string& user, std::string_view payload)> on_publish;
};

struct WsClientStats {
  std::string peer;
  std::uint64_t sent = 0, dropped = 0;
  std::size_t subscriptions = 0;
};

struct WsStats {
  std::vector<WsClientStats> clients;
  std::uint64_t disconnected_garbage = 0;  // clients closed for not speaking the protocol
  std::uint64_t refused = 0;               // connections refused (no subprotocol, not WebSocket, too many)
  std::int64_t bad_requests = 0;           // not HTTP, or a header over 16 KiB (answered 400)
  std::int64_t timeouts = 0;               // no complete upgrade request within 10 s
  std::int64_t refused_connections = 0;    // over max_connections, closed at once
};

class WsServer {
 public:
  // Binds and listens (throws std::runtime_error naming the address if it cannot), then serves on a thread
  // of its own until the destructor.
  explicit WsServer(WsServerOptions options);
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  int bound_port() const;

  // Thread-safe; cheap (no I/O on the caller's thread).
  void advertise(std::vector<WsChannel> channels);
  void unadvertise(const std::vector<int>& channel_ids);
  // Sends a message of a channel to its subscribers; also kept as the channel's last message, sent to a
  // client when it subscribes (outline and path are published once per job).
  void publish(int channel_id, std::uint64_t timestamp_ns, std::shared_ptr<const std::string> payload);
  bool subscribed(int channel_id) const;
  WsStats stats() const;
  // The same, or nothing when another thread holds the lock: for a caller that must not wait (the heartbeat
  // of hg-foxglove, whose conversion thread, at idle priority, may be preempted inside subscribed()).
  std::optional<WsStats> try_stats() const;

  struct Impl;

 private:
  WsStats stats_locked() const;  // with impl_->mu held
  std::shared_ptr<Impl> impl_;
};

}  // namespace hg::foxglove
