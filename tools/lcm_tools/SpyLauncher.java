// tools/spy's entry point: lcm-spy (lcm.spy.Spy from LCM's jar) with a UDP receive buffer that holds the
// plate clouds. LCM's Java multicast provider leaves its socket at the kernel's default receive buffer
// (net.core.rmem_default, ~208 KB) and ignores the URL's recv_buf_size: a message sent as more than a few
// 64 KB fragments overflows it in one burst and is lost whole, so HG_PLATE_CLOUD (~480 KB) never showed and
// HG_DEPTH (~600 KB) only sometimes. This sets the buffer on the provider's socket once Spy has made it
// (recv_buf_size from the URL, default 4 MiB; the kernel caps it at net.core.rmem_max). Run as a
// single-file program, with LCM's jar, jchart2d and the hullgrind types on the class path:
//   java -cp ... SpyLauncher.java [--lcm-url URL] [--check CHANNEL COUNT SECONDS]
// --check: exit 0 once COUNT messages on CHANNEL were decoded into a hullgrind type without an error (print
// the type and its field n), 1 if not within SECONDS: the decoding of tools/spy, tested headless.
import java.lang.reflect.Field;
import java.net.MulticastSocket;
import java.util.HashMap;
import java.util.List;

public class SpyLauncher {
  static final int DEFAULT_BUFFER = 4 << 20;

  static int bufferFromUrl(String url) {
    for (String part : url.replaceFirst("^[^?]*\\?", "").split("&")) {
      if (part.startsWith("recv_buf_size=")) return Integer.parseInt(part.substring("recv_buf_size=".length()));
    }
    return DEFAULT_BUFFER;
  }

  static Object field(Object owner, String name) throws Exception {
    Field f = owner.getClass().getDeclaredField(name);
    f.setAccessible(true);  // package-private in LCM's jar (an unnamed module: open)
    return f.get(owner);
  }

  // Enlarges the receive buffer of every multicast provider of the spy's LCM; returns the size the kernel
  // granted (Linux reports twice the request, for its bookkeeping), 0 when there was no multicast socket.
  static int enlargeReceiveBuffers(lcm.spy.Spy spy, int bytes) throws Exception {
    int granted = 0;
    lcm.lcm.LCM lcm = (lcm.lcm.LCM) field(spy, "lcm");
    for (Object provider : (List<?>) field(lcm, "providers")) {
      if (!(provider instanceof lcm.lcm.UDPMulticastProvider)) continue;
      MulticastSocket sock = (MulticastSocket) field(provider, "sock");
      sock.setReceiveBufferSize(bytes);
      granted = sock.getReceiveBufferSize();
    }
    return granted;
  }

  static int check(lcm.spy.Spy spy, String channel, long count, double seconds) throws Exception {
    long end = System.nanoTime() + (long) (seconds * 1e9);
    while (System.nanoTime() < end) {
      lcm.spy.ChannelData cd;
      synchronized (spy) {
        cd = (lcm.spy.ChannelData) ((HashMap<?, ?>) field(spy, "channelMap")).get(channel);
      }
      if (cd != null && cd.nerrors > 0) {
        System.out.println("check: " + channel + ": " + cd.nerrors + " decode errors");
        return 1;
      }
      if (cd != null && cd.nreceived >= count && cd.cls != null && cd.last != null) {
        Object n = cd.last.getClass().getField("n").get(cd.last);
        System.out.println("check: " + channel + ": " + cd.nreceived + " received, decoded as " + cd.cls.getName() +
                           ", n = " + n);
        return 0;
      }
      Thread.sleep(50);
    }
    System.out.println("check: " + channel + ": not decoded " + count + " times within " + seconds + " s");
    return 1;
  }

  public static void main(String[] args) throws Exception {
    String url = System.getenv().getOrDefault("LCM_DEFAULT_URL", "udpm://239.255.76.67:7667?ttl=0");
    String channel = null;
    long count = 0;
    double seconds = 0;
    for (int i = 0; i < args.length; ++i) {
      if (args[i].equals("--lcm-url")) url = args[++i];
      else if (args[i].startsWith("--lcm-url=")) url = args[i].substring("--lcm-url=".length());
      else if (args[i].equals("--check")) {
        channel = args[++i];
        count = Long.parseLong(args[++i]);
        seconds = Double.parseDouble(args[++i]);
      } else {
        System.err.println("SpyLauncher: unknown argument " + args[i]);
        System.exit(2);
      }
    }
    lcm.spy.Spy spy = new lcm.spy.Spy(url);
    int granted = enlargeReceiveBuffers(spy, bufferFromUrl(url));
    System.out.println("spy: " + url + (granted > 0 ? ", UDP receive buffer " + granted + " bytes" : ""));
    System.out.flush();
    if (channel != null) {
      int code = check(spy, channel, count, seconds);
      System.out.flush();
      System.exit(code);
    }
  }
}
