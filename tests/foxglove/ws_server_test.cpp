// foxglove/ws_server on real sockets (a network namespace of its own), with Boost.Beast's WebSocket client:
// a client that subscribes and then stops reading gets frames dropped and counted while publish() keeps
// returning (the bus is never blocked, the queue stays bounded); a client that sends garbage is closed with
// 1008 and a reason; the subprotocol is negotiated.
#include <gtest/gtest.h>

#include <utility>  // before Boost 1.74's asio (std::exchange under C++20)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

#include "foxglove/ws_server.hpp"

namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using hg::foxglove::WsServer;

struct Client {
  net::io_context ioc;
  websocket::stream<tcp::socket> ws{ioc};
  std::string protocol;

  Client(int port, const std::string& subprotocol, int recv_buffer = 0) {
    tcp::resolver r(ioc);
    net::connect(ws.next_layer(), r.resolve("127.0.0.1", std::to_string(port)));
    if (recv_buffer) ws.next_layer().set_option(net::socket_base::receive_buffer_size(recv_buffer));
    ws.set_option(websocket::stream_base::decorator([subprotocol](websocket::request_type& req) {
      req.set(beast::http::field::sec_websocket_protocol, subprotocol);
    }));
    websocket::response_type res;
    ws.handshake(res, "127.0.0.1", "/");
    protocol = std::string(res[beast::http::field::sec_websocket_protocol]);
  }
  nlohmann::json read_json() {
    beast::flat_buffer b;
    ws.read(b);
    return nlohmann::json::parse(beast::buffers_to_string(b.data()));
  }
};

hg::foxglove::WsServerOptions options() {
  hg::foxglove::WsServerOptions o;
  o.port = 0;
  o.queue_frames = 8;
  o.queue_bytes = 4u << 20;
  return o;
}

TEST(FoxgloveWsServer, SlowClientGetsFramesDroppedAndCountedNeverABlockedPublisher) {
  WsServer server(options());
  server.advertise({{7, "/big", "json", "x", "{}", "jsonschema"}});
  Client c(server.bound_port(), "foxglove.websocket.v1", 16384);
  EXPECT_EQ(c.protocol, "foxglove.websocket.v1");
  EXPECT_EQ(c.read_json()["op"], "serverInfo");
  EXPECT_EQ(c.read_json()["channels"][0]["topic"], "/big");
  c.ws.write(net::buffer(std::string(R"({"op":"subscribe","subscriptions":[{"id":3,"channelId":7}]})")));
  for (int i = 0; i < 100 && !server.subscribed(7); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(server.subscribed(7));
  const int n = 400;
  auto payload = std::make_shared<const std::string>(256 * 1024, 'a');
  for (int i = 0; i < n; ++i) server.publish(7, static_cast<uint64_t>(i), payload);  // the client reads nothing
  std::this_thread::sleep_for(std::chrono::seconds(2));
  auto st = server.stats();
  ASSERT_EQ(st.clients.size(), 1u);
  EXPECT_GT(st.clients[0].dropped, 300u) << "sent " << st.clients[0].sent;
  EXPECT_LE(st.clients[0].dropped + st.clients[0].sent, static_cast<uint64_t>(n));
  // What it did get starts with the first message, framed as the protocol says.
  beast::flat_buffer b;
  c.ws.read(b);
  std::string frame = beast::buffers_to_string(b.data());
  ASSERT_EQ(frame.size(), 13 + payload->size());
  EXPECT_EQ(frame[0], 1);
  EXPECT_EQ(static_cast<unsigned char>(frame[1]), 3u);  // subscription id 3, little endian
  EXPECT_EQ(frame[5], 0);                               // timestamp 0 of the first message
}

TEST(FoxgloveWsServer, GarbageIsClosedWithAReasonAndSdkSubprotocolIsAccepted) {
  WsServer server(options());
  for (const std::string& garbage : {std::string("not json"), std::string(R"({"op":"nonsense"})"),
                                     std::string(R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})")}) {
    Client c(server.bound_port(), "foxglove.sdk.v1");
    EXPECT_EQ(c.protocol, "foxglove.sdk.v1");
    EXPECT_EQ(c.read_json()["op"], "serverInfo");
    c.ws.write(net::buffer(garbage));
    beast::flat_buffer b;
    beast::error_code ec;
    c.ws.read(b, ec);
    EXPECT_EQ(ec, websocket::error::closed) << garbage;
    EXPECT_EQ(c.ws.reason().code, websocket::close_code::policy_error) << garbage;
    EXPECT_FALSE(std::string(c.ws.reason().reason.c_str()).empty()) << garbage;
  }
  EXPECT_EQ(server.stats().disconnected_garbage, 3u);
}

TEST(FoxgloveWsServer, NoFoxgloveSubprotocolIsRefused) {
  WsServer server(options());
  EXPECT_THROW(Client(server.bound_port(), "chat"), beast::system_error);
  EXPECT_GE(server.stats().refused, 1u);
}

}  // namespace
