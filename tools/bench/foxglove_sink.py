#!/usr/bin/env python3
"""A viewer that costs the machine only its socket reads, for the benchmarks (foxglove_bench.py --viewer sink):
the Foxglove WebSocket protocol's client side reduced to what a server sees of a viewer on another computer,
a TCP connection that subscribes and reads. It subscribes to every channel advertised (but those
$HG_VIEWER_EXCLUDE matches, a regular expression), reads every frame in 1 MiB reads and keeps nothing of a
message but its size. On SIGTERM prints one JSON line, as foxglove_client.js: messages and bytes received
per topic (a message's bytes: its Message Data payload after the opcode, subscription id and time).

  tools/bench/foxglove_sink.py [ws://127.0.0.1:8765]

The Foxglove viewers themselves (foxglove_client.js: @foxglove/ws-protocol on node) parse and copy every
message; on a cell they run on the engineer's computer, so the benchmark can compare both. The few lines of
RFC 6455 here are ours because a WebSocket library assembles and copies every message, the very work this
client is there to leave out. It answers the server's pings, as a viewer does."""

import argparse
import base64
import json
import os
import re
import signal
import socket
import struct
import sys
from urllib.parse import urlparse

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.dont_write_bytecode = True  # --help and --version leave no files behind
from hgversion import version  # noqa: E402

SUBPROTOCOL = "foxglove.websocket.v1"


def connect(url):
    u = urlparse(url)
    s = socket.create_connection((u.hostname, u.port or 80))
    key = base64.b64encode(os.urandom(16)).decode()
    s.sendall(("GET / HTTP/1.1\r\nHost: %s:%d\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
               "Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: %s\r\n\r\n"
               % (u.hostname, u.port or 80, key, SUBPROTOCOL)).encode())
    head = b""
    while b"\r\n\r\n" not in head:
        chunk = s.recv(4096)
        if not chunk:
            raise SystemExit("foxglove_sink: the server closed during the upgrade")
        head += chunk
    status = head.split(b"\r\n", 1)[0]
    if b" 101 " not in status:
        raise SystemExit("foxglove_sink: upgrade refused: %s" % status.decode(errors="replace"))
    return s, head.split(b"\r\n\r\n", 1)[1]


def send_frame(s, opcode, data):
    """One masked frame with FIN set (RFC 6455 5.3: a client masks every frame)."""
    mask, n = os.urandom(4), len(data)
    head = bytes([0x80 | opcode]) + (bytes([0x80 | n]) if n < 126 else struct.pack("!BH", 0x80 | 126, n)
                                     if n < 65536 else struct.pack("!BQ", 0x80 | 127, n))
    s.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))


class Reader:
    """Frames out of the byte stream; a message ends at a frame with FIN set (the server may fragment)."""

    def __init__(self, s, buffered):
        self.s, self.buf, self.pos = s, bytearray(buffered), 0
        self.text, self.size, self.head = False, 0, b""

    def fill(self, need):
        while len(self.buf) - self.pos < need:
            if self.pos:
                del self.buf[:self.pos]
                self.pos = 0
            chunk = self.s.recv(1 << 20)
            if not chunk:
                raise EOFError
            self.buf += chunk

    def message(self):
        """(is_text, first 13 bytes or the whole text, size) of the next whole message."""
        while True:
            self.fill(2)
            b0, b1 = self.buf[self.pos], self.buf[self.pos + 1]
            n, at = b1 & 0x7F, 2
            if n == 126:
                self.fill(4)
                n, at = struct.unpack_from("!H", self.buf, self.pos + 2)[0], 4
            elif n == 127:
                self.fill(10)
                n, at = struct.unpack_from("!Q", self.buf, self.pos + 2)[0], 10
            opcode = b0 & 0x0F
            if opcode >= 8:  # control: close, ping (answered with its payload), pong; at most 125 bytes
                self.fill(at + n)
                payload = bytes(self.buf[self.pos + at:self.pos + at + n])
                self.skip(at + n)
                if opcode == 8:
                    raise EOFError
                if opcode == 9:
                    send_frame(self.s, 0xA, payload)
                continue
            if opcode in (1, 2):  # a message's first frame
                self.text, self.size, self.head = opcode == 1, 0, b""
            keep = n if self.text else max(0, min(n, 13 - len(self.head)))  # text: all of it
            self.fill(at + keep)
            self.head += bytes(self.buf[self.pos + at:self.pos + at + keep])
            self.size += n
            self.skip(at + n)
            if b0 & 0x80:
                return self.text, self.head, self.size

    def skip(self, n):
        have = len(self.buf) - self.pos
        if n <= have:
            self.pos += n
            return
        self.pos = len(self.buf)
        n -= have
        while n > 0:
            chunk = self.s.recv(min(n, 1 << 20))
            if not chunk:
                raise EOFError
            n -= len(chunk)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("url", nargs="?", default="ws://127.0.0.1:8765", help="the server (ws://127.0.0.1:8765)")
    ap.add_argument("--version", action="version", version="foxglove_sink.py " + version())
    url = ap.parse_args().url
    exclude = re.compile(os.environ["HG_VIEWER_EXCLUDE"]) if os.environ.get("HG_VIEWER_EXCLUDE") else None
    counts, topics = {}, {}

    def report(*_):
        print(json.dumps(counts), flush=True)
        os._exit(0)

    signal.signal(signal.SIGTERM, report)
    s, rest = connect(url)
    r = Reader(s, rest)
    try:
        while True:
            text, head, size = r.message()
            if text:
                msg = json.loads(head)
                if msg.get("op") == "advertise":
                    subs = []
                    for ch in msg["channels"]:
                        if exclude and exclude.search(ch["topic"]):
                            continue
                        topics[len(topics) + 1] = ch["topic"]
                        subs.append({"id": len(topics), "channelId": ch["id"]})
                    if subs:
                        send_frame(s, 0x1, json.dumps({"op": "subscribe", "subscriptions": subs}).encode())
            elif head[:1] == b"\x01" and len(head) >= 13:
                t = topics.get(struct.unpack_from("<I", head, 1)[0], "?")
                c = counts.setdefault(t, {"messages": 0, "bytes": 0})
                c["messages"] += 1
                c["bytes"] += size - 13
    except (EOFError, OSError):
        pass
    signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGTERM])
    report()


if __name__ == "__main__":
    main()
