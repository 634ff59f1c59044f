// The job's top view (x right, y up, robot base frame) on a 2-D canvas, with a scale bar in mm.
import { KIND_COLOURS, UNREACHED, HOLE, OUTER, EDGE } from "./scene.js";

const css = (c) => "#" + c.toString(16).padStart(6, "0");

// Everything but the TCP is drawn once into a canvas of its own, kept on the canvas until the cloud, outline
// or plan object changes: a pose (10..100 Hz) then costs one copy and one disc, not 40 000 points.
export function drawTop(canvas, { cloud, outline, plan, tcp }) {
  let layer = canvas.hgStatic;
  if (!layer || layer.cloud !== cloud || layer.outline !== outline || layer.plan !== plan ||
      layer.image.width !== canvas.width || layer.image.height !== canvas.height) {
    layer = canvas.hgStatic = { cloud, outline, plan, image: document.createElement("canvas") };
    layer.image.width = canvas.width;
    layer.image.height = canvas.height;
    layer.map = drawStatic(layer.image, cloud, outline, plan);
  }
  const g = canvas.getContext("2d");
  g.drawImage(layer.image, 0, 0);
  if (tcp && layer.map) {
    g.fillStyle = "#ffff00";
    g.beginPath();
    g.arc(layer.map.X(tcp[0]), layer.map.Y(tcp[1]), 5, 0, 2 * Math.PI);
    g.fill();
  }
}

// The cloud, outline, edge and plan with the scale bar; answers the base frame -> pixel maps (null: empty).
function drawStatic(canvas, cloud, outline, plan) {
  const g = canvas.getContext("2d");
  g.fillStyle = "#10161d";
  g.fillRect(0, 0, canvas.width, canvas.height);
  const box = bounds(cloud, outline, plan);
  if (!box) return null;
  const pad = 30, sx = (canvas.width - 2 * pad) / (box.x1 - box.x0), sy = (canvas.height - 2 * pad) / (box.y1 - box.y0);
  const s = Math.min(sx, sy);
  const X = (x) => pad + (x - box.x0) * s, Y = (y) => canvas.height - pad - (y - box.y0) * s;
  if (cloud) {
    g.fillStyle = "#3d5a80";
    const step = Math.max(1, Math.floor(cloud.length / 3 / 40000));
    for (let i = 0; i < cloud.length / 3; i += step) g.fillRect(X(cloud[3 * i]), Y(cloud[3 * i + 1]), 1, 1);
  }
  const poly = (xyz, colour, closed, width) => {
    if (!xyz || xyz.length < 6) return;
    g.strokeStyle = css(colour);
    g.lineWidth = width;
    g.beginPath();
    g.moveTo(X(xyz[0]), Y(xyz[1]));
    for (let i = 3; i < xyz.length; i += 3) g.lineTo(X(xyz[i]), Y(xyz[i + 1]));
    if (closed) g.closePath();
    g.stroke();
  };
  for (const loop of (outline && outline.loops) || []) poly(loop.xyz, loop.hole ? HOLE : OUTER, true, 1);
  for (const e of (plan && plan.edge) || []) poly(e.xyz, EDGE, true, 1);
  if (plan && plan.position) {
    const p = plan.position;
    for (let i = 1; i < plan.kind.length; i++) poly(p.slice(3 * (i - 1), 3 * i + 3), KIND_COLOURS[plan.kind[i]] || 0xffffff, false, 1.5);
    for (const u of plan.unreached || []) poly(u.xyz, UNREACHED, false, 4);
  }
  scaleBar(g, s, canvas.height);
  return { X, Y };
}

function bounds(cloud, outline, plan) {
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  const add = (xyz) => { for (let i = 0; i + 1 < xyz.length; i += 3) { x0 = Math.min(x0, xyz[i]); x1 = Math.max(x1, xyz[i]); y0 = Math.min(y0, xyz[i + 1]); y1 = Math.max(y1, xyz[i + 1]); } };
  if (cloud) add(cloud);
  for (const loop of (outline && outline.loops) || []) add(loop.xyz);
  if (plan && plan.position) add(plan.position);
  if (!(x1 > x0) || !(y1 > y0)) return null;
  return { x0, y0, x1, y1 };
}

// A bar of a round length (1, 2 or 5 x 10^k mm) near a fifth of the canvas.
function scaleBar(g, pxPerM, h) {
  const targetMm = (g.canvas.width / 5) / pxPerM * 1000;
  const k = Math.pow(10, Math.floor(Math.log10(targetMm)));
  const mm = [1, 2, 5, 10].map((f) => f * k).filter((v) => v <= targetMm).pop() || k;
  const px = mm / 1000 * pxPerM;
  g.strokeStyle = "#fff";
  g.fillStyle = "#fff";
  g.lineWidth = 2;
  g.beginPath();
  g.moveTo(10, h - 12); g.lineTo(10 + px, h - 12);
  g.moveTo(10, h - 17); g.lineTo(10, h - 7);
  g.moveTo(10 + px, h - 17); g.lineTo(10 + px, h - 7);
  g.stroke();
  g.font = "12px sans-serif";
  g.fillText(`${mm} mm`, 16 + px, h - 8);
}
