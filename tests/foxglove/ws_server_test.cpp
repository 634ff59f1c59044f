// foxglove/ws_server on real sockets (a network namespace of its own), with Boost.Beast's WebSocket client:
// a client that subscribes and then stops reading gets frames dropped and counted while publish() keeps
// returning (the bus is never blocked, the queue stays bounded); a client that sends garbage is closed with
// 1008 and a reason; the subprotocol is negotiated; a message is one frame, however big.
#include <gtest/gtest.h>

#include <utility>  // before Boost 1.74's asio (std::exchange under C++20)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

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

// A frame's header as RFC 6455 5.2 lays it out, read straight off the socket (a WebSocket library would join
// the frames of a message and hide how many there were); its payload is read and dropped.
struct Frame {
  bool fin = false;
  int opcode = 0;
  std::uint64_t length = 0;
};

Frame read_frame(tcp::socket& s) {
  unsigned char h[2];
  net::read(s, net::buffer(h));
  Frame f{(h[0] & 0x80) != 0, h[0] & 0x0F, h[1] & 0x7Fu};
  const int extra = f.length == 126 ? 2 : f.length == 127 ? 8 : 0;
  if (extra) {
    unsigned char x[8];
    net::read(s, net::buffer(x, extra));
    f.length = 0;
    for (int i = 0; i < extra; ++i) f.length = (f.length << 8) | x[i];
  }
  std::vector<char> payload(f.length);
  net::read(s, net::buffer(payload));
  return f;
}

TEST(FoxgloveWsServer, EveryMessageIsOneFrameHoweverBig) {
  WsServer server(options());
  std::vector<hg::foxglove::WsChannel> channels;
  for (int id = 1; id <= 100; ++id)  // an advertisement of about 10 KB
    channels.push_back({id, "/topic/" + std::to_string(id), "json", "hullgrind.some_type_t", "{}", "jsonschema"});
  server.advertise(channels);
  net::io_context ioc;
  tcp::socket s(ioc);
  tcp::resolver r(ioc);
  net::connect(s, r.resolve("127.0.0.1", std::to_string(server.bound_port())));
  net::write(s, net::buffer(
                    std::string("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
                                "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                                "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n")));
  std::string head;
  for (char c; head.size() < 4 || head.compare(head.size() - 4, 4, "\r\n\r\n") != 0;) {
    net::read(s, net::buffer(&c, 1));  // a byte at a time: nothing of the first frame is read here
    head += c;
  }
  ASSERT_EQ(head.rfind("HTTP/1.1 101", 0), 0u) << head;
  const Frame info = read_frame(s), advert = read_frame(s);
  EXPECT_TRUE(info.fin && info.opcode == 1);
  EXPECT_TRUE(advert.fin && advert.opcode == 1) << "the advertisement came in more than one frame";
  EXPECT_GT(advert.length, 4096u);
  // subscribe, masked as a client must (RFC 6455 5.3); the mask 0 leaves the text as it is
  const std::string sub = R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":7}]})";
  std::string frame = {static_cast<char>(0x81), static_cast<char>(0x80 | sub.size()), 0, 0, 0, 0};
  ASSERT_LT(sub.size(), 126u);
  net::write(s, net::buffer(frame + sub));
  for (int i = 0; i < 100 && !server.subscribed(7); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(server.subscribed(7));
  server.publish(7, 1, std::make_shared<const std::string>(1u << 20, 'a'));
  const Frame data = read_frame(s);
  EXPECT_EQ(data.opcode, 2);
  EXPECT_TRUE(data.fin) << "1 MiB came in more than one frame";
  EXPECT_EQ(data.length, 13u + (1u << 20));
}

TEST(FoxgloveWsServer, NoFoxgloveSubprotocolIsRefused) {
  WsServer server(options());
  EXPECT_THROW(Client(server.bound_port(), "chat"), beast::system_error);
  EXPECT_GE(server.stats().refused, 1u);
}

}  // namespace
