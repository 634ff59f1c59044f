// The WebSocket /api/live: JSON events (statuses, heartbeats, robot poses, new clouds/outlines/paths) and
// binary cloud frames ("HGC1", uint32 n, int64 seq, float32 xyz * n). Reconnects after a drop.
export class Live {
  constructor(onEvent, onCloud) {
    this.onEvent = onEvent;
    this.onCloud = onCloud;
    this.ws = null;
    this.closed = false;
    this.wanted = null;  // the job whose cloud was asked for and has not come
  }

  open() {
    const proto = location.protocol === "https:" ? "wss:" : "ws:";
    const ws = new WebSocket(`${proto}//${location.host}/api/live`);
    ws.binaryType = "arraybuffer";
    ws.onopen = () => this.sendWanted();  // a request made while (re)connecting, or lost with a dropped connection
    ws.onmessage = (m) => {
      if (typeof m.data === "string") return this.onEvent(JSON.parse(m.data));
      this.wanted = null;
      this.onCloud(parseCloud(m.data));
    };
    ws.onclose = () => {
      this.ws = null;
      if (!this.closed) setTimeout(() => this.open(), 2000);
    };
    this.ws = ws;
  }

  // The job's cloud, asked for until a cloud frame arrives: again on every new connection.
  requestCloud(jobId) {
    this.wanted = jobId;
    this.sendWanted();
  }

  sendWanted() {
    if (this.wanted && this.ws && this.ws.readyState === WebSocket.OPEN) this.ws.send(JSON.stringify({ get: "cloud", job: this.wanted }));
  }

  close() {
    this.closed = true;
    if (this.ws) this.ws.close();
  }
}

export function parseCloud(buf) {
  const view = new DataView(buf);
  const magic = String.fromCharCode(view.getUint8(0), view.getUint8(1), view.getUint8(2), view.getUint8(3));
  if (magic !== "HGC1") throw new Error("not a cloud frame");
  const n = view.getUint32(4, true);
  const seq = Number(view.getBigInt64(8, true));
  return { n, seq, xyz: new Float32Array(buf, 16, n * 3) };
}
