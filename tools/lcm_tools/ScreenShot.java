// Screenshots of an X display with java.awt.Robot, for tools/spy-screenshot.sh (Java is already needed by
// lcm-spy, so no image tool has to be installed). Run as a single-file program:
//   java ScreenShot.java ACTION...   with ACTION one of
//     wait MS | click X Y | dblclick X Y | shot FILE.png (the whole screen)
//     grab X Y W H DX DY (copy a screen region into a picture at DX,DY) | save FILE.png (that picture)
// grab/save let two windows that the window-manager-less Xvfb stacks at 0,0 be shown side by side.
import java.awt.Color;
import java.awt.Graphics2D;
import java.awt.Rectangle;
import java.awt.image.BufferedImage;
import java.util.ArrayList;
import java.util.List;
import java.awt.Robot;
import java.awt.Toolkit;
import java.awt.event.InputEvent;
import java.io.File;
import javax.imageio.ImageIO;

public class ScreenShot {
  public static void main(String[] args) throws Exception {
    Robot robot = new Robot();
    record Piece(BufferedImage image, int x, int y) {}
    List<Piece> pieces = new ArrayList<>();
    for (int i = 0; i < args.length; ++i) {
      switch (args[i]) {
        case "wait" -> robot.delay(Integer.parseInt(args[++i]));
        case "click", "dblclick" -> {
          int clicks = args[i].equals("click") ? 1 : 2;
          robot.mouseMove(Integer.parseInt(args[i + 1]), Integer.parseInt(args[i + 2]));
          i += 2;
          for (int c = 0; c < clicks; ++c) {
            robot.mousePress(InputEvent.BUTTON1_DOWN_MASK);
            robot.mouseRelease(InputEvent.BUTTON1_DOWN_MASK);
            robot.delay(60);
          }
        }
        case "shot" -> {
          Rectangle screen = new Rectangle(Toolkit.getDefaultToolkit().getScreenSize());
          File out = new File(args[++i]);
          if (!ImageIO.write(robot.createScreenCapture(screen), "png", out))
            throw new IllegalStateException("no PNG writer");
          System.err.println("ScreenShot: wrote " + out + " (" + screen.width + "x" + screen.height + ")");
        }
        case "grab" -> {
          int[] v = new int[6];
          for (int k = 0; k < 6; ++k) v[k] = Integer.parseInt(args[i + 1 + k]);
          i += 6;
          pieces.add(new Piece(robot.createScreenCapture(new Rectangle(v[0], v[1], v[2], v[3])), v[4], v[5]));
        }
        case "save" -> {
          int w = 1, h = 1;
          for (Piece p : pieces) {
            w = Math.max(w, p.x() + p.image().getWidth());
            h = Math.max(h, p.y() + p.image().getHeight());
          }
          BufferedImage canvas = new BufferedImage(w, h, BufferedImage.TYPE_INT_RGB);
          Graphics2D g = canvas.createGraphics();
          g.setColor(Color.DARK_GRAY);
          g.fillRect(0, 0, w, h);
          for (Piece p : pieces) g.drawImage(p.image(), p.x(), p.y(), null);
          g.dispose();
          File out = new File(args[++i]);
          if (!ImageIO.write(canvas, "png", out)) throw new IllegalStateException("no PNG writer");
          System.err.println("ScreenShot: wrote " + out + " (" + w + "x" + h + ")");
        }
        default -> throw new IllegalArgumentException("unknown action " + args[i]);
      }
    }
  }
}
