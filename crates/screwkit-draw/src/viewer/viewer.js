// screwkit viewer: a chain or a whole tree embedded as JSON (screw axes S at home, each
// joint's parent, link and frame home poses M, limits, mimic rule) and its forward kinematics
// T(q) = Π_{path} e^[S_j]θ_j M, θ = m q + o; each link's shapes (the embedded body) drawn at
// its pose by three.js (inlined before this script), the skeleton, screw axes and frames as
// overlays. Poses are row-major 4 × 4 arrays; twists (ω, v). No network.
"use strict";
(function () {
  const model = JSON.parse(document.getElementById("model").textContent);
  const I4 = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

  function mul(a, b) {
    const c = new Array(16);
    for (let i = 0; i < 4; i++) {
      for (let j = 0; j < 4; j++) {
        c[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + a[4 * i + 3] * b[12 + j];
      }
    }
    return c;
  }
  function cross(a, b) {
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  }
  // e^[S]θ: Rodrigues for the rotation, (Iθ + (1 − cos θ)[ω] + (θ − sin θ)[ω]²) v for the
  // translation (ω scaled to unit length, θ and v scaled with it).
  function exp(S, theta) {
    const wn = Math.hypot(S[0], S[1], S[2]);
    if (wn === 0) {
      return [1, 0, 0, S[3] * theta, 0, 1, 0, S[4] * theta, 0, 0, 1, S[5] * theta, 0, 0, 0, 1];
    }
    const t = theta * wn;
    const u = [S[0] / wn, S[1] / wn, S[2] / wn];
    const v = [S[3] / wn, S[4] / wn, S[5] / wn];
    const s = Math.sin(t), c = Math.cos(t), C = 1 - c;
    const [x, y, z] = u;
    const uv = cross(u, v), uuv = cross(u, uv);
    const p = [0, 1, 2].map((k) => t * v[k] + C * uv[k] + (t - s) * uuv[k]);
    return [
      c + C * x * x, C * x * y - s * z, C * x * z + s * y, p[0],
      C * x * y + s * z, c + C * y * y, C * y * z - s * x, p[1],
      C * x * z - s * y, C * y * z + s * x, c + C * z * z, p[2],
      0, 0, 0, 1,
    ];
  }
  // [Ad_T] S = (R ω, R v + p × R ω).
  function adjoint(T, S) {
    const rot = (a) => [0, 1, 2].map((i) => T[4 * i] * a[0] + T[4 * i + 1] * a[1] + T[4 * i + 2] * a[2]);
    const w = rot(S.slice(0, 3)), v = rot(S.slice(3, 6));
    const pw = cross([T[3], T[7], T[11]], w);
    return [w[0], w[1], w[2], v[0] + pw[0], v[1] + pw[1], v[2] + pw[2]];
  }
  // The floating base's pose from q's first seven values (x, y, z, qx, qy, qz, qw; the
  // quaternion normalised), or the identity for a fixed base.
  const off = model.floating ? 7 : 0;
  function basePose(q) {
    if (!model.floating) return I4;
    let [x, y, z, a, b, c, d] = q.slice(0, 7);
    const n = Math.hypot(a, b, c, d);
    if (n === 0) [a, b, c, d] = [0, 0, 0, 1];
    else [a, b, c, d] = [a / n, b / n, c / n, d / n];
    return [
      1 - 2 * (b * b + c * c), 2 * (a * b - c * d), 2 * (a * c + b * d), x,
      2 * (a * b + c * d), 1 - 2 * (a * a + c * c), 2 * (b * c - a * d), y,
      2 * (a * c - b * d), 2 * (b * c + a * d), 1 - 2 * (a * a + b * b), z,
      0, 0, 0, 1,
    ];
  }
  // The tree (a chain is one branch): G_k = G_parent(k) e^[S_k]θ_k, parents first, with the
  // base's pose for "no parent"; a link or frame is G_support M; the screw of joint k at q is
  // [Ad_{G_parent(k)}] S_k.
  function fk(q) {
    const base = basePose(q);
    const G = [], screws = [];
    model.joints.forEach((j) => {
      const above = j.parent === null ? base : G[j.parent];
      screws.push(adjoint(above, j.S));
      G.push(mul(above, exp(j.S, j.multiplier * q[off + j.variable] + j.offset)));
    });
    const at = (s) => (s === null ? base : G[s]);
    return {
      base,
      links: model.links.map((l) => mul(at(l.support), l.home)),
      frames: model.frames.map((f) => mul(at(f.support), f.home)),
      screws,
    };
  }

  // ---- State: q from the URL (#q=a,b,c) or the embedded default.
  let q = model.q.slice();
  const error = document.getElementById("error");
  function fromHash() {
    const m = /(?:^#|&)q=([^&]*)/.exec(location.hash);
    if (!m) return;
    const parts = decodeURIComponent(m[1]).split(",").filter((x) => x.trim() !== "");
    const vals = parts.map(Number);
    if (vals.length !== model.variables.length || vals.some((x) => !Number.isFinite(x))) {
      error.textContent = `#q= needs ${model.variables.length} finite numbers, got "${m[1]}"`;
      return;
    }
    q = vals;
  }
  fromHash();

  // ---- Side panel.
  document.getElementById("title").textContent = model.robot;
  document.getElementById("chain").textContent = model.subject;
  const select = document.getElementById("frame");
  model.frames.forEach((f, k) => {
    const o = document.createElement("option");
    o.value = k;
    o.textContent = f.name;
    select.append(o);
  });
  select.hidden = model.frames.length < 2;
  document.getElementById("pose-title").textContent =
    model.frames.length < 2 ? "tip pose T(q)" : "frame pose T(q)";
  select.addEventListener("change", () => update());
  const sliders = document.getElementById("sliders");
  const inputs = model.variables.map((v, k) => {
    const row = document.createElement("div");
    row.className = "slider";
    const label = document.createElement("label");
    label.textContent = v.name;
    label.title = v.name + (v.prismatic ? " (m)" : " (rad)");
    const input = document.createElement("input");
    input.type = "range";
    input.min = Number.isFinite(v.lower) ? v.lower : -Math.PI;
    input.max = Number.isFinite(v.upper) ? v.upper : Math.PI;
    input.step = "any";
    input.value = q[k];
    input.id = "q" + k;
    const out = document.createElement("output");
    input.addEventListener("input", () => {
      q[k] = Number(input.value);
      update();
    });
    row.append(label, input, out);
    sliders.append(row);
    return { input, out };
  });
  const fmt = (x) => (Math.abs(x) < 5e-7 ? 0 : x).toFixed(6);
  const fmt4 = (x) => (Math.abs(x) < 5e-5 ? 0 : x).toFixed(4);

  // ---- Drawing, with three.js (WebGL). Without WebGL the tables still follow the sliders.
  const canvas = document.getElementById("view");
  let state = fk(q);
  const home = fk(model.variables.map(() => 0));
  const pts = home.links.map((T) => [T[3], T[7], T[11]]);
  const lo = [0, 1, 2].map((k) => Math.min(...pts.map((p) => p[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...pts.map((p) => p[k])));
  // The view's centre and size: the links' origins at home, then (with WebGL) the body and
  // obstacles as first shown ([`frame`]).
  let centre = lo.map((x, k) => (x + hi[k]) / 2);
  let size = Math.max(Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 0.3);
  const body = model.body || { shapes: [], meshes: [], problems: [] };
  if (body.problems.length) {
    const more = body.problems.length - 1;
    error.textContent = "body: " + body.problems[0] + (more ? ` (and ${more} more)` : "");
    error.title = body.problems.join("\n");
  }
  let az = Math.PI / 4, el = Math.atan(1 / Math.SQRT2), zoom = 1;
  let three = null;
  const traces = new Map();
  try {
    three = makeScene();
    frame();
  } catch (e) {
    error.textContent = "no WebGL in this browser (" + e.message + "): the 3D view is off, the tables follow the sliders";
    error.className = "no-webgl";
  }
  // Row-major 4 × 4 into a three.js matrix (Matrix4.set reads row-major).
  function setMatrix(m, T) {
    m.set(...T);
  }
  function decode(b64, Type) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  function makeScene() {
    const T3 = THREE;
    const renderer = new T3.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    const scene = new T3.Scene();
    scene.background = new T3.Color(0xfbfbf8);
    const camera = new T3.PerspectiveCamera(35, 1, size / 200, size * 200);
    camera.up.set(0, 0, 1);
    scene.add(camera);
    scene.add(new T3.AmbientLight(0xffffff, 1.2));
    const sun = new T3.DirectionalLight(0xffffff, 2.2);
    sun.position.set(1, 2, 3);
    camera.add(sun);
    // Ground grid on the base's xy plane.
    const step = Math.pow(10, Math.floor(Math.log10(size / 2)));
    const n = 2 * Math.ceil(size / step);
    const grid = new T3.GridHelper(n * step, n, 0xd0d0c8, 0xe4e4dc);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(centre[0], centre[1], Math.min(0, lo[2]));
    scene.add(grid);
    // Meshes, decoded once.
    const geometries = body.meshes.map((m) => {
      const g = new T3.BufferGeometry();
      g.setAttribute("position", new T3.BufferAttribute(decode(m.positions, Float32Array), 3));
      g.setIndex(new T3.BufferAttribute(decode(m.indices, Uint32Array), 1));
      g.computeVertexNormals();
      return g;
    });
    function geometryOf(s) {
      switch (s.kind) {
        case "box":
          return new T3.BoxGeometry(s.size[0], s.size[1], s.size[2]);
        case "cylinder":
          return new T3.CylinderGeometry(s.radius, s.radius, s.length, 32).rotateX(Math.PI / 2);
        case "capsule":
          return new T3.CapsuleGeometry(s.radius, s.length, 8, 24).rotateX(Math.PI / 2);
        case "sphere":
          return new T3.SphereGeometry(s.radius, 32, 16);
        case "ellipsoid":
          return new T3.SphereGeometry(1, 32, 16).scale(s.radii[0], s.radii[1], s.radii[2]);
        case "plane":
          return new T3.BoxGeometry(2 * (s.size[0] || size), 2 * (s.size[1] || size), 1e-4 * size);
        case "mesh":
          return geometries[s.mesh];
      }
      return null;
    }
    // Each page link a group placed at its pose; its shapes inside at their origins.
    const groups = model.links.map(() => {
      const g = new T3.Group();
      g.matrixAutoUpdate = false;
      scene.add(g);
      return g;
    });
    const visualOf = new Set(body.shapes.filter((s) => s.role === "visual").map((s) => s.link));
    const shapes = { visual: [], collision: [], obstacle: [] };
    const owners = new Map();
    const framed = [];
    body.shapes.forEach((s) => {
      const geometry = geometryOf(s);
      if (!geometry) return;
      const fallback = { collision: [0.85, 0.45, 0.2, 0.55], obstacle: [0.55, 0.62, 0.7, 0.8] };
      const rgba = s.rgba || fallback[s.role] || [0.7, 0.72, 0.75, 1];
      const material = new T3.MeshStandardMaterial({
        color: new T3.Color(rgba[0], rgba[1], rgba[2]),
        transparent: rgba[3] < 1 || s.role === "collision",
        opacity: s.role === "collision" ? Math.min(rgba[3], 0.55) : rgba[3],
        metalness: 0.1,
        roughness: 0.6,
      });
      const mesh = new T3.Mesh(geometry, material);
      mesh.matrixAutoUpdate = false;
      setMatrix(mesh.matrix, s.origin);
      // Its owner's name (a link's, or an obstacle's), for the contacts' tint.
      const owner = s.link === null ? s.name : model.links[s.link].name;
      (owners.get(owner) || owners.set(owner, []).get(owner)).push({ material, colour: material.color.clone() });
      // An obstacle (link null) stands in the world.
      (s.link === null ? scene : groups[s.link]).add(mesh);
      if (s.kind !== "plane") framed.push(mesh);
      // A link without visual shapes shows its collision shapes as its body.
      const role = s.role === "collision" && !visualOf.has(s.link) ? "visual" : s.role;
      shapes[role].push(mesh);
    });
    // Overlays, drawn over the body.
    function lines(colour) {
      const g = new T3.BufferGeometry();
      const m = new T3.LineBasicMaterial({ color: colour, depthTest: false, transparent: true });
      const l = new T3.LineSegments(g, m);
      l.renderOrder = 10;
      l.frustumCulled = false;
      scene.add(l);
      return l;
    }
    // The skeleton: a rod from each link's parent, a ball at each joint (unit shapes, placed
    // and scaled at each draw).
    const dark = new T3.MeshStandardMaterial({ color: 0x3a3a3a, roughness: 0.8 });
    const rod = new T3.CylinderGeometry(1, 1, 1, 12);
    const ball = new T3.SphereGeometry(1, 16, 8);
    const rods = model.links.map((l) => {
      if (l.parent === null) return null;
      const m = new T3.Mesh(rod, dark);
      m.matrixAutoUpdate = false;
      scene.add(m);
      return m;
    });
    const balls = model.joints.map(() => {
      const m = new T3.Mesh(ball, dark);
      m.matrixAutoUpdate = false;
      scene.add(m);
      return m;
    });
    const overlay = {
      rods,
      balls,
      axes: lines(0x7b3294),
      frames: [lines(0xd7191c), lines(0x1a9641), lines(0x2b83ba)],
      // Minimum-distance segments: red through overlapping shapes, orange between close ones.
      touching: lines(0xd62728),
      close: lines(0xff7f0e),
      // A motion's trace: the shown frame's origin through every motion frame.
      trace: lines(0x009e73),
    };
    return { T3, renderer, scene, camera, groups, shapes, overlay, framed, grid, owners, rod };
  }
  // Frames the view on the body and obstacles as first shown (their box at q, planes left
  // out), with the links' origins: a robot reaching over a table stays in the picture.
  function frame() {
    const { T3, scene, groups, framed, grid, camera } = three;
    groups.forEach((g, k) => setMatrix(g.matrix, state.links[k]));
    scene.updateMatrixWorld(true);
    const box = new T3.Box3();
    state.links.forEach((T) => box.expandByPoint(new T3.Vector3(T[3], T[7], T[11])));
    framed.forEach((m) => box.expandByObject(m));
    if (box.isEmpty()) return;
    const c = box.getCenter(new T3.Vector3());
    centre = [c.x, c.y, c.z];
    size = Math.max(box.getSize(new T3.Vector3()).length(), 0.3);
    camera.near = size / 200;
    camera.far = size * 200;
    grid.position.set(centre[0], centre[1], Math.min(0, box.min.z));
  }
  function setLines(l, points) {
    l.geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(points), 3));
    l.geometry.computeBoundingSphere();
  }
  const toggles = ["visual", "collision", "skeleton", "axes", "frames"].map((k) => document.getElementById("show-" + k));
  const [showVisual, showCollision, showSkeleton, showAxes, showFrames] = toggles;
  const drawn = new Set(body.shapes.filter((s) => s.link !== null).map((s) => s.link));
  if (drawn.size < model.links.length / 2) {
    // Little or nothing to draw of the body (no shapes, or meshes not found): the stick figure.
    showVisual.checked = drawn.size > 0;
    showSkeleton.checked = true;
    // Screw axes for a chain or a small tree (a humanoid's 30 axes hide it).
    showAxes.checked = model.joints.length <= 12;
  }
  toggles.forEach((t) => t.addEventListener("change", () => draw()));
  function draw() {
    if (!three) return;
    const { renderer, scene, camera, groups, shapes, overlay } = three;
    const w = canvas.clientWidth, h = canvas.clientHeight;
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    // The links' box fills the view with room for the shapes around them (35° field of view).
    const dist = (2.3 * size) / zoom;
    const ce = Math.cos(el);
    camera.position.set(
      centre[0] + dist * ce * Math.cos(az),
      centre[1] + dist * ce * Math.sin(az),
      centre[2] + dist * Math.sin(el),
    );
    camera.lookAt(centre[0], centre[1], centre[2]);
    camera.updateProjectionMatrix();
    groups.forEach((g, k) => {
      setMatrix(g.matrix, state.links[k]);
      g.matrixWorldNeedsUpdate = true;
    });
    shapes.visual.forEach((m) => (m.visible = showVisual.checked));
    shapes.collision.forEach((m) => (m.visible = showCollision.checked));
    const L = 0.18 * size;
    // Skeleton: a rod from each link's parent (a unit cylinder along y turned onto the
    // segment), a ball at each joint.
    const T3 = three.T3;
    const r = 0.012 * size;
    const up = new T3.Vector3(0, 1, 0);
    model.links.forEach((l, k) => {
      const m = overlay.rods[k];
      if (!m) return;
      const a = state.links[l.parent], b = state.links[k];
      const pa = new T3.Vector3(a[3], a[7], a[11]), pb = new T3.Vector3(b[3], b[7], b[11]);
      const d = pb.clone().sub(pa);
      const len = d.length();
      const turn = len > 0 ? new T3.Quaternion().setFromUnitVectors(up, d.divideScalar(len)) : new T3.Quaternion();
      m.matrix.compose(pa.add(pb).multiplyScalar(0.5), turn, new T3.Vector3(r, Math.max(len, 1e-9), r));
      m.matrixWorldNeedsUpdate = true;
      m.visible = showSkeleton.checked && len > 0;
    });
    model.joints.forEach((j, k) => {
      const T = state.links[j.link];
      const m = overlay.balls[k];
      m.matrix.compose(new T3.Vector3(T[3], T[7], T[11]), new T3.Quaternion(), new T3.Vector3(2 * r, 2 * r, 2 * r));
      m.matrixWorldNeedsUpdate = true;
      m.visible = showSkeleton.checked;
    });
    // Screw axes at q.
    const ax = [];
    model.joints.forEach((j, k) => {
      const s = state.screws[k];
      const T = state.links[j.link];
      const o = [T[3], T[7], T[11]];
      const wn2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
      if (wn2 === 0) {
        const vn = Math.hypot(s[3], s[4], s[5]);
        ax.push(...o, ...[0, 1, 2].map((i) => o[i] + (L * s[3 + i]) / vn));
      } else {
        const wv = s.slice(0, 3).map((x) => x / Math.sqrt(wn2));
        const p0 = cross(s.slice(0, 3), s.slice(3, 6)).map((x) => x / wn2);
        const d = wv[0] * (o[0] - p0[0]) + wv[1] * (o[1] - p0[1]) + wv[2] * (o[2] - p0[2]);
        const p = [0, 1, 2].map((i) => p0[i] + d * wv[i]);
        ax.push(...[0, 1, 2].map((i) => p[i] - L * wv[i]), ...[0, 1, 2].map((i) => p[i] + L * wv[i]));
      }
    });
    setLines(overlay.axes, ax);
    overlay.axes.visible = showAxes.checked;
    // The base and the drawn frames as RGB triads.
    const tree = model.frames.length > 1;
    [0, 1, 2].forEach((c) => {
      const seg = [];
      [state.base, ...state.frames].forEach((T, f) => {
        const len = (tree && f > 0 ? 0.05 : 0.12) * size;
        seg.push(T[3], T[7], T[11], T[3] + len * T[c], T[7] + len * T[4 + c], T[11] + len * T[8 + c]);
      });
      setLines(overlay.frames[c], seg);
      overlay.frames[c].visible = showFrames.checked;
    });
    // The body's contacts at this configuration, when the page holds them.
    const red = new T3.Color(0xd62728);
    const colliding = new Set(contactsNow ? contactsNow.collisions.flat() : []);
    three.owners.forEach((list, name) =>
      list.forEach((m) => m.material.color.copy(colliding.has(name) ? red : m.colour)),
    );
    const touching = [], close = [];
    ((contactsNow && contactsNow.close) || []).forEach((p) =>
      (p.distance < 0 ? touching : close).push(...p.points[0], ...p.points[1]),
    );
    setLines(overlay.touching, touching);
    setLines(overlay.close, close);
    setLines(overlay.trace, traceOf(Number(select.value) || 0));
    renderer.render(scene, camera);
  }

  // ---- A motion's trace: frame f's origin at each motion frame, as segments (computed once
  // per frame shown, in `traces`).
  function traceOf(f) {
    if (!model.motion || !model.frames.length) return [];
    if (!traces.has(f)) {
      const pts = [];
      let prev = null;
      model.motion.frames.forEach((qk) => {
        const T = fk(qk).frames[f];
        const p = [T[3], T[7], T[11]];
        if (prev) pts.push(...prev, ...p);
        prev = p;
      });
      traces.set(f, pts);
    }
    return traces.get(f);
  }

  // ---- The body's contacts, computed by the library at the first configuration and at each
  // motion frame: shown while the page is at one of those, said to be unknown elsewhere.
  let contactsNow = null;
  const same = (a, b) => a.length === b.length && a.every((x, k) => x === b[k]);
  function contactsAt() {
    const c = model.contacts;
    if (!c) return null;
    if (model.motion) {
      const k = Number(document.getElementById("time").value);
      if (c.frames[k] && same(q, model.motion.frames[k])) return c.frames[k];
    }
    return same(q, model.q) ? c.q : null;
  }
  function showContacts() {
    const c = model.contacts;
    if (!c) return;
    document.getElementById("contacts").hidden = false;
    const state = document.getElementById("contact-state");
    const table = document.getElementById("contact-pairs");
    table.innerHTML = "";
    if (!contactsNow) {
      state.textContent = "known at the first pose" + (model.motion ? " and the motion's frames" : "") +
        " only: the library computes them (" + c.pairs + " pairs)";
      return;
    }
    const n = contactsNow.collisions.length;
    state.textContent = (n ? `${n} pair${n > 1 ? "s" : ""} in collision (red)` : "no collision") +
      ` of ${c.pairs} pairs checked` + (c.within ? `; pairs closer than ${c.within * 1000} mm:` : "");
    if (!c.within) {
      contactsNow.collisions.slice(0, 10).forEach((p) => {
        table.insertRow().insertCell().textContent = p[0] + " – " + p[1];
      });
      if (n > 10) table.insertRow().insertCell().textContent = `(and ${n - 10} more)`;
    }
    // The closest ten; the rest counted.
    const near = (c.within && contactsNow.close) || [];
    near.slice(0, 10).forEach((p) => {
      const tr = table.insertRow();
      const name = tr.insertCell();
      name.textContent = p.pair[0] + " – " + p.pair[1];
      name.title = name.textContent;
      tr.insertCell().textContent = (p.distance * 1000).toFixed(1) + " mm";
    });
    if (near.length > 10) table.insertRow().insertCell().textContent = `(and ${near.length - 10} more)`;
  }

  // ---- Tables and the exact values the tests read.
  function update() {
    state = fk(q);
    inputs.forEach((x, k) => {
      x.input.value = q[k];
      x.out.textContent = q[k].toFixed(4);
    });
    const tip = document.getElementById("tip");
    tip.innerHTML = "";
    const shown = state.frames[Number(select.value) || 0] || I4;
    for (let i = 0; i < 4; i++) {
      const tr = tip.insertRow();
      for (let j = 0; j < 4; j++) tr.insertCell().textContent = fmt(shown[4 * i + j]);
    }
    const screws = document.getElementById("screws");
    screws.innerHTML = "<tr><th>#</th><th>joint</th><th>ω</th><th>v</th></tr>";
    model.joints.forEach((j, k) => {
      const s = state.screws[k];
      const tr = screws.insertRow();
      tr.insertCell().textContent = k + 1;
      const name = tr.insertCell();
      name.textContent = j.name;
      name.style.textAlign = "left";
      tr.insertCell().textContent = s.slice(0, 3).map(fmt4).join(" ");
      tr.insertCell().textContent = s.slice(3, 6).map(fmt4).join(" ");
    });
    contactsNow = contactsAt();
    showContacts();
    document.getElementById("q-exact").textContent = JSON.stringify(q);
    document.getElementById("fk-exact").textContent = JSON.stringify([].concat(...state.frames));
    draw();
  }

  // ---- A motion played back: frame k of model.motion.frames at k / fps seconds.
  if (model.motion) {
    const frames = model.motion.frames, fps = model.motion.fps;
    const player = document.getElementById("player");
    const play = document.getElementById("play");
    const time = document.getElementById("time");
    const clock = document.getElementById("clock");
    player.hidden = false;
    time.max = frames.length - 1;
    let playing = false, t0 = 0, k0 = 0;
    const show = (k) => {
      time.value = k;
      clock.textContent = `frame ${k + 1} / ${frames.length}, ${(k / fps).toFixed(3)} s at ${fps} fps`;
      q = frames[k].slice();
      update();
    };
    const tick = (now) => {
      if (!playing) return;
      // (A frame's timestamp may precede the click's: never a negative step.)
      const k = (k0 + Math.max(0, Math.floor(((now - t0) / 1000) * fps))) % frames.length;
      if (k !== Number(time.value)) show(k);
      requestAnimationFrame(tick);
    };
    play.addEventListener("click", () => {
      playing = !playing;
      play.textContent = playing ? "pause" : "play";
      if (playing) {
        t0 = performance.now();
        k0 = Number(time.value);
        requestAnimationFrame(tick);
      }
    });
    time.addEventListener("input", () => {
      playing = false;
      play.textContent = "play";
      show(Number(time.value));
    });
    clock.textContent = `frame 1 / ${frames.length}, 0.000 s at ${fps} fps`;
    // #play in the URL starts it (#q=… still sets the first pose shown).
    if (/(?:^#|&)play(?:&|$)/.test(location.hash)) play.click();
  }

  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    drag = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    az -= (e.clientX - drag[0]) * 0.01;
    el = Math.max(-1.5, Math.min(1.5, el + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  canvas.addEventListener("pointerup", () => (drag = null));
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    zoom *= Math.exp(-e.deltaY * 0.001);
    draw();
  }, { passive: false });
  window.addEventListener("resize", draw);
  window.addEventListener("hashchange", () => {
    fromHash();
    update();
  });
  update();
})();
