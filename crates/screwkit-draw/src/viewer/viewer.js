// screwkit viewer: a chain or a whole tree embedded as JSON (screw axes S at home, each
// joint's parent, link and frame home poses M, limits, mimic rule) and its forward kinematics
// T(q) = Π_{path} e^[S_j]θ_j M, θ = m q + o, drawn on a canvas. Poses are row-major 4 × 4 arrays; twists (ω, v). No network, no library.
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

  // ---- Drawing.
  const canvas = document.getElementById("view");
  const ctx = canvas.getContext("2d");
  let az = Math.PI / 4, el = Math.atan(1 / Math.SQRT2), zoom = 1;
  let state = fk(q);
  const home = fk(model.variables.map(() => 0));
  const pts = home.links.map((T) => [T[3], T[7], T[11]]);
  const lo = [0, 1, 2].map((k) => Math.min(...pts.map((p) => p[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...pts.map((p) => p[k])));
  const centre = lo.map((x, k) => (x + hi[k]) / 2);
  const size = Math.max(Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 1e-3);
  function project(p) {
    const x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    const ca = Math.cos(az), sa = Math.sin(az), ce = Math.cos(el), se = Math.sin(el);
    const right = -sa * x + ca * y;
    const depth = ca * x + sa * y;
    const up = z * ce - depth * se;
    const w = canvas.width, h = canvas.height;
    const scale = (0.8 * Math.min(w, h) / size) * zoom;
    return [w / 2 + right * scale, h / 2 - up * scale];
  }
  function seg(a, b, colour, width, dash) {
    const p = project(a), r = project(b);
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.setLineDash(dash || []);
    ctx.beginPath();
    ctx.moveTo(p[0], p[1]);
    ctx.lineTo(r[0], r[1]);
    ctx.stroke();
  }
  function draw() {
    const dpr = window.devicePixelRatio || 1;
    canvas.width = canvas.clientWidth * dpr;
    canvas.height = canvas.clientHeight * dpr;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    ctx.lineCap = "round";
    // Ground grid on the base's xy plane.
    const step = Math.pow(10, Math.floor(Math.log10(size / 2)));
    const n = Math.ceil(size / step);
    for (let i = -n; i <= n; i++) {
      const g = "#e4e4dc";
      seg([centre[0] + i * step, centre[1] - n * step, 0], [centre[0] + i * step, centre[1] + n * step, 0], g, 1);
      seg([centre[0] - n * step, centre[1] + i * step, 0], [centre[0] + n * step, centre[1] + i * step, 0], g, 1);
    }
    const L = 0.18 * size;
    // Screw axes at q.
    model.joints.forEach((j, k) => {
      const s = state.screws[k];
      const T = state.links[j.link];
      const o = [T[3], T[7], T[11]];
      const wn2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
      if (wn2 === 0) {
        const vn = Math.hypot(s[3], s[4], s[5]);
        seg(o, [0, 1, 2].map((i) => o[i] + (L * s[3 + i]) / vn), "#008837", 3);
      } else {
        const w = s.slice(0, 3).map((x) => x / Math.sqrt(wn2));
        const p0 = cross(s.slice(0, 3), s.slice(3, 6)).map((x) => x / wn2);
        const d = w[0] * (o[0] - p0[0]) + w[1] * (o[1] - p0[1]) + w[2] * (o[2] - p0[2]);
        const p = [0, 1, 2].map((i) => p0[i] + d * w[i]);
        seg([0, 1, 2].map((i) => p[i] - L * w[i]), [0, 1, 2].map((i) => p[i] + L * w[i]), "#7b3294", 2, [8, 4]);
        const e = project([0, 1, 2].map((i) => p[i] + L * w[i]));
        ctx.fillStyle = "#7b3294";
        ctx.font = `${12 * dpr}px sans-serif`;
        ctx.fillText(String(k + 1), e[0] + 4, e[1] - 4);
      }
    });
    // Links: a segment from each link's parent (the previous link on a chain).
    model.links.forEach((l, k) => {
      if (l.parent === null) return;
      const a = state.links[l.parent], b = state.links[k];
      seg([a[3], a[7], a[11]], [b[3], b[7], b[11]], "#3a3a3a", 5 * dpr);
    });
    // The base and the drawn frames (the tip, or every leaf with its name).
    // A tree's leaves get short triads and their names, moved down or up by a line off the
    // names already written.
    const tree = model.frames.length > 1;
    const placed = [];
    ctx.font = `${11 * dpr}px sans-serif`;
    [state.base, ...state.frames].forEach((T, f) => {
      const o = [T[3], T[7], T[11]];
      const len = (tree && f > 0 ? 0.05 : 0.12) * size;
      ["#d7191c", "#1a9641", "#2b83ba"].forEach((c, k) => {
        seg(o, [0, 1, 2].map((i) => o[i] + len * T[4 * i + k]), c, 2.5 * dpr);
      });
      if (f > 0 && tree) {
        const name = model.frames[f - 1].name;
        const e = project(o);
        const x = e[0] + 8 * dpr, w = ctx.measureText(name).width, line = 13 * dpr;
        const free = (y) => placed.every((b) => x + w <= b[0] || b[0] + b[2] <= x || Math.abs(y - b[1]) >= line);
        let y = e[1] + 14 * dpr;
        for (let k = 0; k <= 16; k++) {
          const t = e[1] + 14 * dpr + (k % 2 ? 1 : -1) * Math.floor((k + 1) / 2) * line;
          if (free(t)) {
            y = t;
            break;
          }
        }
        placed.push([x, y, w]);
        ctx.fillStyle = "#222222";
        ctx.fillText(name, x, y);
      }
    });
    // Joints.
    ctx.setLineDash([]);
    model.joints.forEach((j) => {
      const T = state.links[j.link];
      const c = project([T[3], T[7], T[11]]);
      ctx.fillStyle = "#ffffff";
      ctx.strokeStyle = "#3a3a3a";
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      if (j.kind === "prismatic") ctx.rect(c[0] - 6 * dpr, c[1] - 6 * dpr, 12 * dpr, 12 * dpr);
      else ctx.arc(c[0], c[1], 6 * dpr, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    });
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
    document.getElementById("q-exact").textContent = JSON.stringify(q);
    document.getElementById("fk-exact").textContent = JSON.stringify([].concat(...state.frames));
    draw();
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
