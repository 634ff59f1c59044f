// The /hg/grind_path SceneUpdate against the hullgrind.grind_path_t it came from (shared by mcap_check.js
// and live_check.js): entity "smoothed_edge" has one line loop per run of equal edge_loop values, its points
// exactly the edge's points in order, in a colour that no path segment and no outline loop has.
"use strict";

// The edge's rings as the message gives them: [{loop, points: [[x, y, z], ...]}], split where edge_loop changes
// (the message's edge is num_edge_points x 3 values, row-major).
function edgeRings(path) {
  const rings = [];
  for (let i = 0; i < path.num_edge_points; ++i) {
    if (i === 0 || path.edge_loop[i] !== path.edge_loop[i - 1]) rings.push({ loop: path.edge_loop[i], points: [] });
    rings[rings.length - 1].points.push(path.edge.slice(3 * i, 3 * i + 3));
  }
  return rings;
}

const colorKey = (c) => `${c.r},${c.g},${c.b}`;
// The colours the bridge gives path segments of each kind and outline loops (docs/foxglove.md, "Topics"):
// a job's messages need not show every kind, so the edge is checked against them all as well.
const PALETTE = ["0.3,0.5,1", "1,0.85,0.1", "1,0.35,0", "0.8,0.9,0.1", "0.7,0.3,0.9", "0.6,0.6,0.6", "1,1,1",
                 "0.1,0.8,0.3", "0.9,0.15,0.15"];

// Returns the reasons the scene does not show the path's smoothed edge ([] when it does); outlineColorKeys:
// the colours of the outlines seen (outlineColors).
function checkSmoothedEdge(scene, path, outlineColorKeys = []) {
  const failures = [];
  const entity = (id) => scene.entities.find((e) => e.id === id);
  const edge = entity("smoothed_edge"), route = entity("grind_path");
  if (!edge || !route) return [`entities ${scene.entities.map((e) => e.id)}: no smoothed_edge or grind_path`];
  const rings = edgeRings(path);
  if (edge.lines.length !== rings.length)
    failures.push(`smoothed_edge has ${edge.lines.length} lines, the path's edge ${rings.length} loops`);
  rings.forEach((ring, k) => {
    const line = edge.lines[k];
    if (!line) return;
    if (line.type !== 1) failures.push(`edge loop ${ring.loop}: line type ${line.type}, not LINE_LOOP (1)`);
    const same = line.points.length === ring.points.length &&
                 ring.points.every((p, i) => line.points[i].x === p[0] && line.points[i].y === p[1] && line.points[i].z === p[2]);
    if (!same) failures.push(`edge loop ${ring.loop}: ${line.points.length} points, not the edge's ${ring.points.length}`);
  });
  const others = new Set(PALETTE);
  for (const l of route.lines) for (const c of [l.color, ...l.colors]) others.add(colorKey(c));
  for (const line of edge.lines)
    if (others.has(colorKey(line.color)) || outlineColorKeys.includes(colorKey(line.color)))
      failures.push(`edge colour ${colorKey(line.color)} is also a path or outline colour`);
  return failures;
}

// The colours of an /hg/outline SceneUpdate's lines.
function outlineColors(scene) {
  return scene.entities.flatMap((e) => e.lines.map((l) => colorKey(l.color)));
}

module.exports = { checkSmoothedEdge, outlineColors, edgeRings };
