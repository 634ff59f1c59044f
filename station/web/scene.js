// The job's 3-D view (three.js r111 from Debian's libjs-three): the plate cloud coloured by height, the
// outline (holes in another colour), the smoothed edge the planner measured coverage on, the tool path
// coloured by kind, unreached stretches in red, the TCP (a disc on a 2-D canvas over the WebGL one).
// What was drawn is on the container's data attributes (cloud and edge points, renders, TCP poses heard and
// drawn); the first render of each cloud is the performance mark "hg-cloud-drawn", the first with cloud and
// plan "hg-job-drawn": the browser tests and tools/bench/station_bench.py read them.
import * as THREE from "/three/build/three.module.js";
import { OrbitControls } from "/three/examples/jsm/controls/OrbitControls.js";

export const KIND_COLOURS = [0x7f8fa6, 0x43a047, 0xff9800, 0x00acc1, 0x8e24aa, 0xbbbbbb];
export const UNREACHED = 0xff1744, HOLE = 0x40c4ff, OUTER = 0xffffff, EDGE = 0xff40ff;

export class Scene3D {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x10161d);
    container.appendChild(this.renderer.domElement);
    // The TCP on a 2-D canvas over the WebGL one: a pose (10..100 Hz) redraws one disc, not the 200 000-point
    // scene (software GL on a cell PC without a GPU manages a few such frames a second).
    this.overlay = document.createElement("canvas");
    this.overlay.className = "tcp-overlay";
    container.appendChild(this.overlay);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(0.5, -1.2, 1.2);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener("change", () => this.render());
    this.groups = { cloud: new THREE.Group(), outline: new THREE.Group(), edge: new THREE.Group(), path: new THREE.Group() };
    this.stats = { cloudPoints: 0, edgePoints: 0, renders: 0, tcpPoses: 0, tcpDraws: 0 };
    this.cloudNew = false;
    this.tcpNew = false;
    for (const g of Object.values(this.groups)) this.scene.add(g);
    this.tcp = null;  // the TCP's position, base frame (m)
    this.scene.add(new THREE.AxesHelper(0.1));
    this.framed = false;
    window.addEventListener("resize", () => this.resize());
    this.resize();
  }

  resize() {
    const w = this.container.clientWidth || 560, h = this.container.clientHeight || 420;
    this.renderer.setSize(w, h);
    const r = window.devicePixelRatio || 1;
    this.overlay.width = Math.round(w * r);
    this.overlay.height = Math.round(h * r);
    this.overlay.style.width = w + "px";
    this.overlay.style.height = h + "px";
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // One render per animation frame however many updates came in it: the robot's pose arrives at up to
  // 100 Hz, and each render of a 200 000-point cloud is costly (software GL on a cell PC without a GPU).
  render() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.renderer.render(this.scene, this.camera);
      this.stats.renders++;
      if (this.cloudNew) performance.mark("hg-cloud-drawn");
      if (!this.jobDrawn && this.stats.cloudPoints && this.groups.path.children.length) {
        this.jobDrawn = true;  // the first frame with the cloud and the plan: the job view's first render
        performance.mark("hg-job-drawn");
      }
      this.cloudNew = false;
      this.drawTcp();
    });
  }

  // The TCP alone, at most once per animation frame, unless a whole render is due in that frame anyway.
  renderTcp() {
    if (this.pending || this.tcpPending) return;
    this.tcpPending = true;
    requestAnimationFrame(() => {
      this.tcpPending = false;
      if (!this.pending) this.drawTcp();
    });
  }

  // The TCP as a yellow disc at its projection through the 3-D view's camera; the counters on the dataset.
  drawTcp() {
    const o = this.overlay, g = o.getContext("2d");
    g.clearRect(0, 0, o.width, o.height);
    if (this.tcp) {
      const v = new THREE.Vector3(this.tcp[0], this.tcp[1], this.tcp[2]).project(this.camera);
      if (v.z > -1 && v.z < 1) {
        const r = window.devicePixelRatio || 1;
        g.fillStyle = "#ffff00";
        g.strokeStyle = "#000";
        g.lineWidth = r;
        g.beginPath();
        g.arc((v.x + 1) / 2 * o.width, (1 - v.y) / 2 * o.height, 5 * r, 0, 2 * Math.PI);
        g.fill();
        g.stroke();
      }
    }
    if (this.tcpNew) this.stats.tcpDraws++;
    this.tcpNew = false;
    const d = this.container.dataset;
    d.cloudPoints = this.stats.cloudPoints;
    d.edgePoints = this.stats.edgePoints;
    d.renders = this.stats.renders;
    d.tcpPoses = this.stats.tcpPoses;
    d.tcpDraws = this.stats.tcpDraws;
  }

  clear(group) {
    const g = this.groups[group];
    while (g.children.length) {
      const c = g.children.pop();
      c.geometry.dispose();
      c.material.dispose();
    }
  }

  setCloud(xyz) {
    this.clear("cloud");
    const n = xyz.length / 3;
    let zmin = Infinity, zmax = -Infinity;
    for (let i = 0; i < n; i++) { const z = xyz[3 * i + 2]; if (z < zmin) zmin = z; if (z > zmax) zmax = z; }
    const span = zmax - zmin > 1e-6 ? zmax - zmin : 1;
    const colours = new Float32Array(n * 3), c = new THREE.Color();
    for (let i = 0; i < n; i++) {
      c.setHSL(0.66 * (1 - (xyz[3 * i + 2] - zmin) / span), 0.8, 0.5);  // blue low ... red high
      colours.set([c.r, c.g, c.b], 3 * i);
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.BufferAttribute(xyz, 3));
    geo.setAttribute("color", new THREE.BufferAttribute(colours, 3));
    this.groups.cloud.add(new THREE.Points(geo, new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: THREE.VertexColors })));
    this.stats.cloudPoints = n;
    this.cloudNew = true;
    this.frame(geo);
    this.render();
  }

  line(group, xyz, colour, closed) {
    if (xyz.length < 6) return;
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(xyz), 3));
    const Kind = closed ? THREE.LineLoop : THREE.Line;
    // Drawn over the cloud: the outline and unreached stretches lie in the plate's plane, where the cloud's
    // points would hide them.
    const line = new Kind(geo, new THREE.LineBasicMaterial({ color: colour, depthTest: false }));
    line.renderOrder = 1;
    this.groups[group].add(line);
    if (!this.framed) this.frame(geo);
  }

  // A polyline's vertices as 5-pixel dots over everything: WebGL draws lines 1 pixel wide, too thin to see
  // an unreached stretch in red next to the edge it lies on.
  dots(group, xyz, colour) {
    if (xyz.length < 3) return;
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(xyz), 3));
    const dots = new THREE.Points(geo, new THREE.PointsMaterial({ color: colour, size: 5, sizeAttenuation: false, depthTest: false }));
    dots.renderOrder = 2;
    this.groups[group].add(dots);
  }

  setOutline(outline) {
    this.clear("outline");
    if (!outline || !outline.loops) return;
    for (const loop of outline.loops) this.line("outline", loop.xyz, loop.hole ? HOLE : OUTER, true);
    this.render();
  }

  // The smoothed edge the tool grinds (base frame, a closed ring per loop), drawn over the cloud like the
  // outline: where the coverage and the unreached stretches are measured.
  setEdge(edge) {
    this.clear("edge");
    let n = 0;
    for (const e of edge || []) {
      this.line("edge", e.xyz, EDGE, true);
      n += e.xyz.length >= 6 ? e.xyz.length / 3 : 0;
    }
    this.stats.edgePoints = n;
    this.render();
  }

  // Consecutive waypoints of one kind as one line of that kind's colour (each stretch starts at the previous
  // waypoint, so the path has no gaps); unreached stretches on top, in red.
  setPlan(plan) {
    this.clear("path");
    if (!plan || !plan.position) return;
    const p = plan.position, kind = plan.kind, n = kind.length;
    // The segment that ends at waypoint i has kind[i]; a run of equal kinds is one line from its first
    // segment's start waypoint to its last segment's end waypoint.
    for (let s = 0; s + 1 < n;) {
      let e = s + 1;
      while (e + 1 < n && kind[e + 1] === kind[s + 1]) e++;
      this.line("path", p.slice(3 * s, 3 * e + 3), KIND_COLOURS[kind[s + 1]] || 0xffffff, false);
      s = e;
    }
    for (const u of plan.unreached || []) {
      this.line("path", u.xyz, UNREACHED, false);
      this.dots("path", u.xyz, UNREACHED);
    }
    this.render();
  }

  setTcp(xyz) {
    this.tcp = xyz;
    this.tcpNew = true;
    this.stats.tcpPoses++;
    this.renderTcp();
  }

  frame(geo) {
    geo.computeBoundingSphere();
    const s = geo.boundingSphere;
    if (!s || !isFinite(s.radius) || s.radius <= 0) return;
    this.controls.target.copy(s.center);
    this.camera.position.set(s.center.x, s.center.y - 2.2 * s.radius, s.center.z + 2.2 * s.radius);
    this.camera.near = s.radius / 100;
    this.camera.far = s.radius * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.framed = true;
  }
}
