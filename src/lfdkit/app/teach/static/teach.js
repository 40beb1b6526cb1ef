/* lfdkit teach: draw demonstrations, learn a skill, try it live.
 *
 * Hand-written, no library. The drawing (demonstrations with their times,
 * obstacles, marks) lives here, in this tab; the server keeps this tab's
 * learned skill under a session id it hands out when the page loads, and
 * every request carries that id in the X-Lfdkit-Session header.
 * World coordinates are metres (the robot's base at the origin).
 */
"use strict";

(function () {
  const SESSION_HEADER = "X-Lfdkit-Session";
  const CLASS_COLORS = { obstacle: "#9a9a9a", cup: "#17becf", marker: "#2ca02c" };
  const EXTRA_COLORS = ["#9467bd", "#e377c2", "#8c564b", "#bcbd22", "#ff7f0e"];
  const DEMO_COLORS = ["#4c72b0", "#55a868", "#c44e52", "#8172b2", "#ccb974", "#64b5cd",
    "#dd8452", "#937860", "#da8bc3", "#8c8c8c"];
  // Inferno, as lfdkit.plot draws rewards (REWARD_CMAP).
  const CMAP = [[0, 0, 4], [40, 11, 84], [101, 21, 110], [159, 42, 99], [212, 72, 66],
    [245, 125, 21], [250, 193, 39], [252, 255, 164]];
  const MIN_STEP_PX = 1.5;
  const MIN_POINTS = 5;
  const HEAT_NX = 84, HEAT_NY = 48;
  const FRAME_PLAN_COLOR = "#f28e2b"; // the task-frame skill's plan: apart from green/red, purple, blue

  const $ = (id) => document.getElementById(id);
  const canvas = $("canvas");
  const ctx = canvas.getContext("2d");
  const dspace = $("dspace");

  const state = {
    session: null,
    limits: null,
    view: [-0.7, 0.7, 0.0, 0.8],
    defaultView: [-0.7, 0.7, 0.0, 0.8],
    mode: "teach",
    tool: "draw",
    demos: [], // {id, points: [[x, y]], times: [s] | null, obstacles: [ids], frames: {name: [x, y, angle]} | null}
    frames: [], // task frames on the table {name, x, y, angle (rad)}: each new stroke records their poses
    obstacles: [], // teach obstacles {id, class, x, y, radius, table: bool[, shape: "box", width, depth, yaw]}
    nextDemo: 1,
    nextObstacle: 1,
    selected: null, // {kind: "demo"|"obstacle"|"trial", id}
    stroke: null,
    drag: null,
    undo: [],
    layers: null,
    learning: false,
    trial: { start: null, goal: null, obstacles: [], frames: [] }, // frames: {name, x, y, angle (rad)}
    plan: null,
    planError: null,
    framePlan: null, // the task-frame skill's plan for trial.frames (POST /api/plan/frames)
    framePlanError: null,
    framePlanBusy: false,
    framePlanCount: 0,
    heat: null,
    heatImage: null,
    roundTrip: null,
    planBusy: false,
    planCount: 0,
    show: { heat: true, band: true, demos: true, path: true, nominal: true, plan: true, frames: true },
  };

  // ------------------------------------------------------------ server
  async function api(method, path, body, raw) {
    const headers = {};
    if (state.session) headers[SESSION_HEADER] = state.session;
    let payload;
    if (raw !== undefined) {
      payload = raw;
      headers["Content-Type"] = "application/octet-stream";
    } else if (body !== undefined) {
      payload = JSON.stringify(body);
      headers["Content-Type"] = "application/json";
    }
    let response;
    try {
      response = await fetch(path, { method, headers, body: payload });
    } catch (err) {
      throw new Error("the server does not answer (was lfdkit teach stopped?)");
    }
    const type = response.headers.get("content-type") || "";
    if (!response.ok) {
      let text = `the server answered ${response.status}`;
      if (type.includes("json")) {
        const data = await response.json();
        if (data && data.error) text = data.error;
      }
      throw new Error(text);
    }
    return response;
  }
  async function apiJson(method, path, body) {
    return (await api(method, path, body)).json();
  }

  function showMessage(text, kind) {
    $("message-text").textContent = text;
    $("message").className = kind === "info" ? "info" : "";
    $("message").hidden = false;
  }
  function clearMessage() { $("message").hidden = true; }
  function fail(err) { showMessage(err && err.message ? err.message : String(err)); }

  // ------------------------------------------------------------ geometry
  const W = () => canvas.width / devicePixelRatioUsed;
  const H = () => canvas.height / devicePixelRatioUsed;
  let devicePixelRatioUsed = 1;
  function toPx(x, y) {
    const [x0, x1, y0, y1] = state.view;
    return [(x - x0) / (x1 - x0) * W(), H() - (y - y0) / (y1 - y0) * H()];
  }
  function toWorld(px, py) {
    const [x0, x1, y0, y1] = state.view;
    return [x0 + px / W() * (x1 - x0), y0 + (H() - py) / H() * (y1 - y0)];
  }
  function pxPerMetre() { return W() / (state.view[1] - state.view[0]); }
  function eventWorld(ev) {
    const rect = canvas.getBoundingClientRect();
    const px = (ev.clientX - rect.left) / rect.width * W();
    const py = (ev.clientY - rect.top) / rect.height * H();
    return toWorld(px, py);
  }
  function distPx(a, b) { return Math.hypot(a[0] - b[0], a[1] - b[1]) * pxPerMetre(); }
  function round(v, d) { const f = 10 ** d; return Math.round(v * f) / f; }

  function classColor(name) {
    if (CLASS_COLORS[name]) return CLASS_COLORS[name];
    let h = 0;
    for (const c of name) h = (h * 31 + c.charCodeAt(0)) >>> 0;
    return EXTRA_COLORS[h % EXTRA_COLORS.length];
  }
  function demoColor(index) { return DEMO_COLORS[index % DEMO_COLORS.length]; }

  // ------------------------------------------------------------ undo
  function snapshot() {
    state.undo.push(JSON.stringify({
      demos: state.demos, obstacles: state.obstacles, frames: state.frames, trial: state.trial,
    }));
    if (state.undo.length > 60) state.undo.shift();
  }
  function undo() {
    const last = state.undo.pop();
    if (!last) { showMessage("nothing to undo", "info"); return; }
    const saved = JSON.parse(last);
    state.demos = saved.demos;
    state.obstacles = saved.obstacles;
    state.frames = saved.frames || [];
    state.trial = saved.trial;
    state.selected = null;
    refresh();
    if (state.mode === "try") { requestPlan(true); requestFramePlan(); showFrameAngle(); }
  }

  // ------------------------------------------------------------ drawing
  function resize() {
    const ratio = window.devicePixelRatio || 1;
    devicePixelRatioUsed = ratio;
    canvas.width = 980 * ratio;
    canvas.height = 560 * ratio;
    dspace.width = 980 * ratio;
    dspace.height = 150 * ratio;
    draw();
  }

  function line(points, color, width, dash) {
    if (!points || points.length < 2) return;
    ctx.save();
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.lineJoin = "round";
    ctx.lineCap = "round";
    if (dash) ctx.setLineDash(dash);
    ctx.beginPath();
    points.forEach((p, i) => {
      const [px, py] = toPx(p[0], p[1]);
      if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
    });
    ctx.stroke();
    ctx.restore();
  }

  // A round grid step for the view: about 14 lines across (1, 2 or 5 times a power of ten).
  function gridStep() {
    const raw = (state.view[1] - state.view[0]) / 14;
    const power = 10 ** Math.floor(Math.log10(raw));
    return [1, 2, 5, 10].map((m) => m * power).find((v) => v >= raw);
  }
  function lengthLabel(metres) {
    if (metres >= 1) return `${round(metres, 3)} m`;
    if (metres >= 0.01) return `${round(metres * 100, 3)} cm`;
    return `${round(metres * 1000, 3)} mm`;
  }

  function drawGrid(dark) {
    const [x0, x1, y0, y1] = state.view;
    const minor = dark ? "rgba(255,255,255,0.06)" : "#f1f3f5";
    const majorColor = dark ? "rgba(255,255,255,0.14)" : "#e3e7eb";
    const step = gridStep();
    const digits = Math.max(0, -Math.floor(Math.log10(step * 2)) + 1);
    ctx.save();
    ctx.font = "11px system-ui, sans-serif";
    // Text on a light patch over the heat map: readable on any of its colours.
    const label = (text, x, y) => {
      if (dark) {
        ctx.fillStyle = "rgba(255,255,255,0.7)";
        ctx.fillRect(x - 2, y - 10, ctx.measureText(text).width + 4, 13);
      }
      ctx.fillStyle = dark ? "#1d232b" : "#8a939e";
      ctx.fillText(text, x, y);
    };
    for (let k = Math.ceil(x0 / step); k * step <= x1 + 1e-12; k++) {
      const [px] = toPx(k * step, 0);
      const major = k % 2 === 0;
      ctx.strokeStyle = major ? majorColor : minor;
      ctx.beginPath(); ctx.moveTo(px, 0); ctx.lineTo(px, H()); ctx.stroke();
      if (major) label(`${round(k * step, digits)}`, px + 3, H() - 4);
    }
    for (let k = Math.ceil(y0 / step); k * step <= y1 + 1e-12; k++) {
      const [, py] = toPx(0, k * step);
      const major = k % 2 === 0;
      ctx.strokeStyle = major ? majorColor : minor;
      ctx.beginPath(); ctx.moveTo(0, py); ctx.lineTo(W(), py); ctx.stroke();
      if (major && k * step > y0 + 1e-12) label(`${round(k * step, digits)}`, 3, py - 3);
    }
    label("x, y in metres", W() - 88, 14);
    // Scale bar: one grid step.
    const [bx, by] = [16, H() - 24];
    const len = step * pxPerMetre();
    ctx.fillStyle = "rgba(255,255,255,0.8)";
    ctx.fillRect(bx - 6, by - 19, len + 12, 25);
    ctx.strokeStyle = "#1d232b";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(bx, by - 4); ctx.lineTo(bx, by); ctx.lineTo(bx + len, by); ctx.lineTo(bx + len, by - 4);
    ctx.stroke();
    ctx.fillStyle = "#1d232b";
    ctx.fillText(lengthLabel(step), bx + len / 2 - 14, by - 6);
    // The robot's base at the origin.
    const [ox, oy] = toPx(0, 0);
    ctx.strokeStyle = dark ? "rgba(255,255,255,0.5)" : "#b9c1ca";
    ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(ox, oy, 0.05 * pxPerMetre(), Math.PI, 2 * Math.PI); ctx.stroke();
    label("robot base", ox - 26, oy - 0.05 * pxPerMetre() - 4);
    ctx.restore();
  }

  // A box's corners in metres (its radius rounds it: drawn as the sharp box grown by it).
  function boxCorners(o) {
    const c = Math.cos(o.yaw || 0), s = Math.sin(o.yaw || 0);
    const hw = o.width / 2 + o.radius, hd = o.depth / 2 + o.radius;
    return [[-hw, -hd], [hw, -hd], [hw, hd], [-hw, hd]].map(([u, v]) => [o.x + c * u - s * v, o.y + s * u + c * v]);
  }

  // What the server reads of an obstacle (parse_obstacles): a round one or a box.
  function obstacleJson(o) {
    const item = { id: o.id, class: o.class, x: o.x, y: o.y, radius: o.radius };
    if (o.shape === "box") Object.assign(item, { shape: "box", width: o.width, depth: o.depth, yaw: o.yaw || 0 });
    return item;
  }

  function drawObstacle(o, options) {
    const [px, py] = toPx(o.x, o.y);
    let r = Math.max(o.radius * pxPerMetre(), 3);
    const color = classColor(o.class);
    ctx.save();
    ctx.globalAlpha = options.faint ? 0.45 : 1;
    ctx.fillStyle = color + "55";
    ctx.strokeStyle = color;
    ctx.lineWidth = options.selected ? 3 : 1.6;
    if (options.dashed) ctx.setLineDash([4, 3]);
    ctx.beginPath();
    if (o.shape === "box") {
      boxCorners(o).forEach((p, i) => { const [qx, qy] = toPx(p[0], p[1]); if (i) ctx.lineTo(qx, qy); else ctx.moveTo(qx, qy); });
      ctx.closePath();
      r = Math.max(Math.hypot(o.width, o.depth) / 2 * pxPerMetre(), 3);
    } else {
      ctx.arc(px, py, r, 0, 2 * Math.PI);
    }
    ctx.fill(); ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = options.dark ? "#ffffff" : "#1d232b";
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillText(options.label || o.class, px + r + 3, py - r / 2);
    ctx.restore();
  }

  // The learned class's term around an obstacle: where exp(-(x-O)ᵀP(x-O)) = 1/e.
  function drawReach(o, dark) {
    if (o.shape === "box") return; // a box's response follows its extent, not one ellipse
    const c = state.layers.classes.find((k) => k.name === o.class);
    if (!c || c.reach.some((r) => r === null)) return;
    const [px, py] = toPx(o.x, o.y);
    const axis = c.axes[0];
    ctx.save();
    ctx.strokeStyle = dark ? "rgba(255,255,255,0.8)" : classColor(o.class);
    ctx.lineWidth = 1.2;
    ctx.setLineDash([5, 4]);
    ctx.beginPath();
    ctx.ellipse(px, py, c.reach[0] * pxPerMetre(), c.reach[1] * pxPerMetre(),
      -Math.atan2(axis[1], axis[0]), 0, 2 * Math.PI);
    ctx.stroke();
    ctx.restore();
  }

  // A task frame: its x axis (red) and y axis (green), 5 cm each, and its name.
  const FRAME_AXIS = 0.05;
  function drawFrame(f, options) {
    const [px, py] = toPx(f.x, f.y);
    const c = Math.cos(f.angle), s = Math.sin(f.angle);
    ctx.save();
    ctx.globalAlpha = options.faint ? 0.5 : 1;
    ctx.lineWidth = options.selected ? 3.5 : 2.2;
    if (options.faint) ctx.setLineDash([4, 3]);
    [["#d62728", c, s], ["#2ca02c", -s, c]].forEach(([color, ux, uy]) => {
      const [qx, qy] = toPx(f.x + FRAME_AXIS * ux, f.y + FRAME_AXIS * uy);
      ctx.strokeStyle = color;
      ctx.beginPath(); ctx.moveTo(px, py); ctx.lineTo(qx, qy); ctx.stroke();
    });
    ctx.setLineDash([]);
    ctx.fillStyle = "#1d232b";
    ctx.strokeStyle = "#ffffff";
    ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(px, py, 3.5, 0, 2 * Math.PI); ctx.fill();
    if (options.patch) { // in Try: a ring in the plan's colour marks the frame as a handle
      ctx.stroke();
      ctx.strokeStyle = FRAME_PLAN_COLOR;
      ctx.lineWidth = 2.5;
      ctx.beginPath(); ctx.arc(px, py, 8, 0, 2 * Math.PI); ctx.stroke();
    }
    ctx.font = "11px system-ui, sans-serif";
    const text = options.label || f.name;
    if (options.patch) { // readable on any colour of the heat map
      ctx.fillStyle = "rgba(255,255,255,0.8)";
      ctx.fillRect(px + 4, py + 4, ctx.measureText(text).width + 4, 13);
      ctx.fillStyle = "#1d232b";
    }
    ctx.fillText(text, px + 6, py + 14);
    ctx.restore();
  }

  // The task-frame skill's plan, labelled at its end. A dark rim, not the obstacle plan's
  // white one: orange alone fades into the reward's yellows and oranges.
  function drawFramePlan() {
    const plan = state.framePlan;
    if (!plan) return;
    line(plan.points, "#1d232b", 6);
    line(plan.points, FRAME_PLAN_COLOR, 3.2);
    const end = plan.points[plan.points.length - 1];
    const [px, py] = toPx(end[0], end[1]);
    ctx.save();
    ctx.font = "bold 11px system-ui, sans-serif";
    const text = "task-frame plan";
    ctx.fillStyle = "rgba(255,255,255,0.85)";
    ctx.fillRect(px + 8, py - 20, ctx.measureText(text).width + 6, 15);
    ctx.fillStyle = "#b35806";
    ctx.fillText(text, px + 11, py - 9);
    ctx.restore();
  }

  function drawHandle(point, color, letter) {
    const [px, py] = toPx(point[0], point[1]);
    ctx.save();
    ctx.fillStyle = color;
    ctx.strokeStyle = "#fff";
    ctx.lineWidth = 2;
    ctx.beginPath(); ctx.arc(px, py, 9, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    ctx.fillStyle = "#fff";
    ctx.font = "bold 11px system-ui, sans-serif";
    ctx.fillText(letter, px - 4, py + 4);
    ctx.restore();
  }

  function heatColor(v) {
    const x = Math.min(Math.max(v, 0), 1) * (CMAP.length - 1);
    const i = Math.min(Math.floor(x), CMAP.length - 2);
    const f = x - i;
    return CMAP[i].map((c, k) => Math.round(c + f * (CMAP[i + 1][k] - c)));
  }

  function makeHeatImage(heat) {
    const off = document.createElement("canvas");
    off.width = heat.nx;
    off.height = heat.ny;
    const g = off.getContext("2d");
    const image = g.createImageData(heat.nx, heat.ny);
    for (let j = 0; j < heat.ny; j++) {
      const row = heat.values[j];
      for (let i = 0; i < heat.nx; i++) {
        const [r, gg, b] = heatColor(row[i]);
        const k = ((heat.ny - 1 - j) * heat.nx + i) * 4; // rows come from ymin up
        image.data[k] = r; image.data[k + 1] = gg; image.data[k + 2] = b; image.data[k + 3] = 255;
      }
    }
    g.putImageData(image, 0, 0);
    return off;
  }

  function drawHeat() {
    if (!state.heat || !state.heatImage) return;
    const [x0, x1, y0, y1] = state.heat.view;
    const [ax, ay] = toPx(x0, y1);
    const [bx, by] = toPx(x1, y0);
    // Cell centres sit on the grid's corners: stretch by half a cell either way.
    const hx = (bx - ax) / (state.heat.nx - 1) / 2, hy = (by - ay) / (state.heat.ny - 1) / 2;
    ctx.save();
    ctx.globalAlpha = 0.8;
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(state.heatImage, ax - hx, ay - hy, bx - ax + 2 * hx, by - ay + 2 * hy);
    ctx.restore();
  }

  function drawBand() {
    const layers = state.layers;
    if (!layers) return;
    const path = layers.path, normals = layers.normals, rows = layers.distance_space;
    const low = [], high = [];
    for (let i = 0; i < path.length; i++) {
      let lo = 0, hi = 0;
      for (const row of rows) {
        const v = row[i];
        if (v === null) continue;
        lo = Math.min(lo, v); hi = Math.max(hi, v);
      }
      low.push([path[i][0] + normals[i][0] * lo, path[i][1] + normals[i][1] * lo]);
      high.push([path[i][0] + normals[i][0] * hi, path[i][1] + normals[i][1] * hi]);
    }
    ctx.save();
    ctx.fillStyle = "rgba(31, 111, 180, 0.16)";
    ctx.beginPath();
    high.concat(low.reverse()).forEach((p, i) => {
      const [px, py] = toPx(p[0], p[1]);
      if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
    });
    ctx.closePath();
    ctx.fill();
    ctx.restore();
  }

  function draw() {
    ctx.setTransform(devicePixelRatioUsed, 0, 0, devicePixelRatioUsed, 0, 0);
    ctx.clearRect(0, 0, W(), H());
    const trying = state.mode === "try" && state.layers;
    const dark = trying && state.show.heat && state.heatImage !== null;
    if (dark) drawHeat();
    drawGrid(dark);
    if (trying) {
      if (state.show.band) drawBand();
      if (state.show.demos) state.demos.forEach((d) => line(d.points, "rgba(90,98,110,0.45)", 1));
      if (state.show.path) line(state.layers.path, "#1f6fb4", 2.5, [8, 5]);
      if (state.show.nominal && state.plan) line(state.plan.nominal, "#8e44ad", 2, [3, 4]);
      if (state.show.plan && state.plan) {
        const ok = state.plan.collision_free;
        line(state.plan.points, "#ffffff", 6);
        line(state.plan.points, ok ? "#1a9850" : "#d73027", 3.2);
      }
      const framed = state.layers.task_frames && state.show.frames;
      if (framed) drawFramePlan();
      state.trial.obstacles.forEach((o) => drawReach(o, dark));
      state.trial.obstacles.forEach((o) => drawObstacle(o, {
        dark,
        selected: state.selected && state.selected.kind === "trial" && state.selected.id === o.id,
      }));
      drawHandle(state.trial.start, "#1a9850", "S");
      drawHandle(state.trial.goal, "#d73027", "G");
      // Over the handles: a frame often stands where the path starts or ends.
      if (framed) (state.trial.frames || []).forEach((f) => drawFrame(f, {
        patch: true,
        selected: state.selected && state.selected.kind === "trialframe" && state.selected.id === f.name,
        label: `⊹ ${f.name}`,
      }));
    } else {
      state.obstacles.forEach((o) => drawObstacle(o, {
        dashed: !o.table,
        faint: !o.table,
        selected: state.selected && state.selected.kind === "obstacle" && state.selected.id === o.id,
        label: `${o.class} ${o.id}`,
      }));
      state.demos.forEach((d, i) => {
        const selected = state.selected && state.selected.kind === "demo" && state.selected.id === d.id;
        line(d.points, demoColor(i), selected ? 4 : 2.2, d.obstacles.length ? [7, 4] : null);
        const [px, py] = toPx(d.points[0][0], d.points[0][1]);
        ctx.fillStyle = demoColor(i);
        ctx.beginPath(); ctx.arc(px, py, 3, 0, 2 * Math.PI); ctx.fill();
      });
      // The frames as the selected demonstration recorded them, then those on the table.
      const shown = state.selected && state.selected.kind === "demo" && state.demos.find((d) => d.id === state.selected.id);
      if (shown && shown.frames) {
        Object.entries(shown.frames).forEach(([name, [x, y, angle]]) => drawFrame({ name, x, y, angle }, { faint: true, label: `${name} (${shown.id})` }));
      }
      state.frames.forEach((f) => drawFrame(f, {
        selected: state.selected && state.selected.kind === "frame" && state.selected.id === f.name,
      }));
      if (state.stroke) line(state.stroke.points, "#1d232b", 2.2);
    }
    drawDistanceSpace();
  }

  function drawDistanceSpace() {
    const layers = state.layers;
    dspace.hidden = !(layers && state.mode === "try" && state.show.band);
    if (dspace.hidden) return;
    const g = dspace.getContext("2d");
    const w = dspace.width / devicePixelRatioUsed, h = dspace.height / devicePixelRatioUsed;
    g.setTransform(devicePixelRatioUsed, 0, 0, devicePixelRatioUsed, 0, 0);
    g.clearRect(0, 0, w, h);
    const rows = layers.distance_space;
    let extent = 0.01;
    rows.forEach((row) => row.forEach((v) => { if (v !== null) extent = Math.max(extent, Math.abs(v)); }));
    const m = layers.path.length;
    const left = 52, right = 10, top = 20, bottom = 22;
    const X = (i) => left + i / (m - 1) * (w - left - right);
    const Y = (v) => top + (1 - (v + extent) / (2 * extent)) * (h - top - bottom);
    g.font = "11px system-ui, sans-serif";
    g.fillStyle = "#1d232b";
    g.fillText("Distance-Space: signed distance of each clean demonstration from the generalized path", left, 13);
    g.strokeStyle = "#d8dde3";
    g.strokeRect(left, top, w - left - right, h - top - bottom);
    g.fillStyle = "#66707c";
    g.fillText(`${round(extent * 100, 1)} cm`, 4, top + 8);
    g.fillText(`-${round(extent * 100, 1)} cm`, 4, h - bottom);
    g.fillText("path point →", w - right - 70, h - 6);
    rows.forEach((row, j) => {
      g.strokeStyle = demoColor(j);
      g.lineWidth = 1.3;
      g.beginPath();
      let open = false;
      row.forEach((v, i) => {
        if (v === null) { open = false; return; }
        if (!open) g.moveTo(X(i), Y(v)); else g.lineTo(X(i), Y(v));
        open = true;
      });
      g.stroke();
    });
    g.strokeStyle = "#1f6fb4";
    g.lineWidth = 2;
    g.setLineDash([8, 5]);
    g.beginPath(); g.moveTo(X(0), Y(0)); g.lineTo(X(m - 1), Y(0)); g.stroke();
    g.setLineDash([]);
  }

  // ------------------------------------------------------------ panels
  function el(tag, attrs, text) {
    const node = document.createElement(tag);
    Object.entries(attrs || {}).forEach(([k, v]) => {
      if (k === "className") node.className = v; else node.setAttribute(k, v);
    });
    if (text !== undefined) node.textContent = text;
    return node;
  }

  function demoDuration(d) {
    return d.times && d.times.length ? d.times[d.times.length - 1] - d.times[0] : null;
  }

  function renderLists() {
    const olist = $("obstacle-list");
    olist.replaceChildren();
    if (!state.obstacles.length) olist.append(el("li", { className: "empty" }, "none yet: pick ◯ and click the canvas"));
    state.obstacles.forEach((o) => {
      const li = el("li", { "data-id": o.id });
      if (state.selected && state.selected.kind === "obstacle" && state.selected.id === o.id) li.className = "selected";
      const sw = el("span", { className: "swatch" });
      sw.style.background = classColor(o.class);
      const name = el("span", { className: "name" }, `${o.id} ${o.class}`);
      name.onclick = () => { state.selected = { kind: "obstacle", id: o.id }; refresh(); };
      const size = o.shape === "box"
        ? `▭ ${round(o.width * 100, 1)}×${round(o.depth * 100, 1)} cm${o.yaw ? ` ${round((o.yaw * 180) / Math.PI, 0)}°` : ""}`
        : `r ${round(o.radius * 100, 1)} cm`;
      const meta = el("span", { className: "meta" }, size);
      const table = el("label", { className: "meta" });
      const box = el("input", { type: "checkbox" });
      box.checked = o.table;
      box.onchange = () => { snapshot(); o.table = box.checked; refresh(); };
      table.append(box, " on table");
      const del = el("button", { className: "del", type: "button", title: "delete", "aria-label": `delete ${o.id}` }, "×");
      del.onclick = () => deleteObstacle(o.id);
      li.append(sw, name, meta, table, del);
      olist.append(li);
    });
    const flist = $("frame-list");
    flist.replaceChildren();
    if (!state.frames.length) flist.append(el("li", { className: "empty" }, "none: pick ⊹ and click where an object of the task stands"));
    state.frames.forEach((f) => {
      const li = el("li", { "data-id": f.name });
      if (state.selected && state.selected.kind === "frame" && state.selected.id === f.name) li.className = "selected";
      const name = el("span", { className: "name" }, `⊹ ${f.name}`);
      name.onclick = () => { state.selected = { kind: "frame", id: f.name }; $("frame-angle").value = round((f.angle * 180) / Math.PI, 0); refresh(); };
      const meta = el("span", { className: "meta" },
        `${round(f.x * 100, 1)}, ${round(f.y * 100, 1)} cm, ${round((f.angle * 180) / Math.PI, 0)}°`);
      const del = el("button", { className: "del", type: "button", title: "delete", "aria-label": `delete frame ${f.name}` }, "×");
      del.onclick = () => deleteFrame(f.name);
      li.append(name, meta, del);
      flist.append(li);
    });
    const dlist = $("demo-list");
    dlist.replaceChildren();
    if (!state.demos.length) dlist.append(el("li", { className: "empty" }, "none yet: draw strokes from start to goal"));
    state.demos.forEach((d, i) => {
      const li = el("li", { "data-id": d.id });
      if (state.selected && state.selected.kind === "demo" && state.selected.id === d.id) li.className = "selected";
      const sw = el("span", { className: "swatch" });
      sw.style.background = demoColor(i);
      const name = el("span", { className: "name" }, d.id);
      name.onclick = () => { state.selected = { kind: "demo", id: d.id }; refresh(); };
      const duration = demoDuration(d);
      const framesSaid = d.frames ? `, ⊹ ${Object.keys(d.frames).length}` : "";
      const meta = el("span", { className: "meta" },
        `${d.points.length} pts${duration !== null ? `, ${round(duration, 2)} s` : ""}${framesSaid}`);
      li.append(sw, name, meta);
      // Every obstacle's chip on the selected demonstration (or with few obstacles);
      // on the others only the marked ones, so that long lists stay short.
      const open = state.obstacles.length <= 3 || (state.selected && state.selected.kind === "demo" && state.selected.id === d.id);
      state.obstacles.forEach((o) => {
        const on = d.obstacles.includes(o.id);
        if (!on && !open) return;
        const chip = el("button", { type: "button", className: on ? "chip on" : "chip", title: `swerved around ${o.id}?` }, o.id);
        if (on) { chip.style.background = classColor(o.class); chip.style.borderColor = classColor(o.class); }
        chip.onclick = () => {
          snapshot();
          d.obstacles = on ? d.obstacles.filter((k) => k !== o.id) : d.obstacles.concat([o.id]);
          refresh();
        };
        li.append(chip);
      });
      if (!d.obstacles.length) li.append(el("span", { className: "meta" }, "clean"));
      const del = el("button", { className: "del", type: "button", title: "delete", "aria-label": `delete ${d.id}` }, "×");
      del.onclick = () => deleteDemo(d.id);
      li.append(del);
      dlist.append(li);
    });
  }

  function renderStatus() {
    const clean = state.demos.filter((d) => !d.obstacles.length).length;
    const framed = state.layers && state.layers.task_frames;
    const learned = state.layers
      ? `skill learned (${state.layers.classes.map((c) => c.name).join(", ") || "no obstacle class"})` +
        (framed ? ` + task-frame skill (⊹ ${framed.frames.join(", ")})` : "")
      : "no skill yet";
    const n = state.frames.length;
    const frames = n ? ` · ${n} task frame${n > 1 ? "s" : ""}` : "";
    $("status").textContent = `${state.demos.length} demonstrations (${clean} clean) · ${state.obstacles.length} obstacles${frames} · ${learned}`;
    const hints = {
      draw: "Draw each demonstration from start to goal with the mouse, a pen or a finger; its speed is kept.",
      obstacle: "Click to place an obstacle of the class and radius above; drag one to move it; Delete removes the selected one.",
      frame: "Click to place a task frame (an object the task acts on) or move the one of that name; drag it, turn it with the angle. Each new stroke records where the frames are: move them between strokes, then export demos.csv for lfdkit learn --task-frames.",
      try: "Drag S, G and the obstacles: the plan follows. Green: collision-free; red: it touches an obstacle.",
      tryFrames: " Drag the task frames (⊹) and turn them below: the orange task-frame plan follows them.",
    };
    $("hint").textContent = state.mode === "try" ? hints.try + (framed ? hints.tryFrames : "") : hints[state.tool];
    document.querySelector('#modes [data-mode="try"]').disabled = !state.layers;
    document.querySelectorAll("#modes button").forEach((b) => b.classList.toggle("on", b.dataset.mode === state.mode));
    $("teach-panel").hidden = state.mode === "try";
    $("try-panel").hidden = state.mode !== "try";
    $("learn").disabled = state.learning;
    $("try-frames").hidden = !framed;
    $("frames-layer").hidden = !framed;
    $("export-frame-skill").disabled = !framed;
  }

  function renderPlanInfo() {
    const info = $("plan-info");
    info.replaceChildren();
    if (state.planError) {
      info.append(el("span", { className: "bad" }, "no plan: "), state.planError);
      return;
    }
    const p = state.plan;
    if (!p) return;
    const verdict = p.collision_free
      ? el("span", { className: "ok" }, "✓ collision-free")
      : el("span", { className: "bad" }, `✗ ${p.collisions} collision${p.collisions === 1 ? "" : "s"}`);
    const clear = p.min_clearance === null ? "no obstacle" : `clearance ${round(p.min_clearance * 100, 1)} cm`;
    info.append(verdict, ` · ${clear} · ${p.points.length} points, ${round(p.duration, 2)} s`);
    info.append(el("br"));
    info.append(el("span", { className: "meta" },
      `round trip ${Math.round(state.roundTrip)} ms (planner ${Math.round(p.plan_ms)} ms) · ends ${round(p.goal_error * 1000, 1)} mm from the goal`));
  }

  function renderFramePlanInfo() {
    const info = $("frame-plan-info");
    info.replaceChildren();
    if (!state.layers || !state.layers.task_frames) return;
    if (state.framePlanError) {
      info.append(el("span", { className: "bad" }, "no task-frame plan: "), state.framePlanError);
      return;
    }
    const p = state.framePlan;
    if (!p) return;
    const key = el("i", { className: "key frames" });
    info.append(key, ` task-frame plan: ${p.points.length} points, ${round(p.duration, 2)} s (planner ${Math.round(p.plan_ms)} ms)`);
    p.warnings.forEach((w) => { info.append(el("br"), el("span", { className: "warn" }, `⚠ ${w}`)); });
  }

  function renderClasses() {
    const table = $("classes");
    table.replaceChildren();
    const layers = state.layers;
    if (!layers) return;
    const head = el("tr");
    head.append(el("th", {}, "term"), el("th", {}, "parameters"), el("th", {}, "reach (1/e)"));
    table.append(head);
    if (layers.nominal_weight !== null) {
      const tr = el("tr");
      tr.append(el("td", {}, "nominal Q"), el("td", { className: "num" }, `${layers.nominal_weight.toPrecision(4)} /m²`), el("td", {}, ""));
      table.append(tr);
    }
    layers.classes.forEach((c) => {
      const tr = el("tr");
      const name = el("td");
      const sw = el("span", { className: "swatch" });
      sw.style.background = classColor(c.name);
      name.append(sw, ` ${c.name}`);
      const p = c.precision.map((row) => row.map((v) => v.toPrecision(3)).join("  ")).join(" | ");
      const reach = c.reach.map((r) => (r === null ? "∞" : `${round(r * 100, 1)}`)).join(" × ") + " cm";
      tr.append(name, el("td", { className: "num", title: "precision matrix P, 1/m²" }, `P = [${p}]`), el("td", { className: "num" }, reach));
      table.append(tr);
    });
    const tr = el("tr");
    const fit = layers.fit;
    tr.append(el("td", {}, "fit"), el("td", { colspan: "2" },
      `${fit.mimic} of ${fit.n_clean} clean demos; DMP ${layers.dmp_basis} basis; ` +
      `${round(layers.timing.duration, 2)} s (${layers.timing.source}); ` +
      `reward from ${fit.n_obstacle} demos${fit.converged === false ? " (did not converge)" : ""}`));
    table.append(tr);
    if (layers.task_frames) {
      const row = el("tr");
      row.append(el("td", {}, "⊹ frames"), el("td", { colspan: "2" }, `task-frame skill: ${layers.task_frames.summary}`));
      table.append(row);
    }
    const select = $("try-class");
    select.replaceChildren();
    layers.classes.forEach((c) => select.append(el("option", { value: c.name }, c.name)));
    $("add-obstacle").disabled = !layers.classes.length;
  }

  function refresh() {
    renderLists();
    renderStatus();
    draw();
  }

  // ------------------------------------------------------------ editing
  function deleteDemo(id) {
    snapshot();
    state.demos = state.demos.filter((d) => d.id !== id);
    state.selected = null;
    refresh();
  }
  function deleteObstacle(id) {
    snapshot();
    state.obstacles = state.obstacles.filter((o) => o.id !== id);
    state.demos.forEach((d) => { d.obstacles = d.obstacles.filter((k) => k !== id); });
    state.selected = null;
    refresh();
  }
  function deleteFrame(name) {
    snapshot();
    state.frames = state.frames.filter((f) => f.name !== name);
    state.selected = null;
    refresh();
  }
  function deleteSelected() {
    const s = state.selected;
    if (!s) return;
    if (s.kind === "frame") deleteFrame(s.id);
    else if (s.kind === "demo") deleteDemo(s.id);
    else if (s.kind === "obstacle") deleteObstacle(s.id);
    else if (s.kind === "trial") {
      snapshot();
      state.trial.obstacles = state.trial.obstacles.filter((o) => o.id !== s.id);
      state.selected = null;
      requestPlan(true);
    }
  }

  function newObstacleId(taken) {
    let id;
    do { id = `o${state.nextObstacle++}`; } while (taken.some((o) => o.id === id));
    return id;
  }
  function newDemoId() {
    let id;
    do { id = `demo-${state.nextDemo++}`; } while (state.demos.some((d) => d.id === id));
    return id;
  }

  function obstacleInputs() {
    const name = $("obstacle-class").value.trim();
    const radius = Number($("obstacle-radius").value) / 100;
    if (!/^[A-Za-z0-9][A-Za-z0-9_.-]*$/.test(name) || name.length > 40) {
      throw new Error("obstacle class: a plain name (letters, digits, '_', '-', '.')");
    }
    const shape = $("obstacle-shape").value;
    if (shape === "box") {
      const width = Number($("box-width").value) / 100, depth = Number($("box-depth").value) / 100;
      const yaw = (Number($("box-yaw").value) * Math.PI) / 180;
      if (!(width > 0 && width <= 2 && depth > 0 && depth <= 2)) throw new Error("box: edges of 0.5 to 200 cm");
      if (!Number.isFinite(yaw)) throw new Error("box: turned by a number of degrees");
      return { name, radius: 0, shape, width, depth, yaw };
    }
    if (!(radius > 0 && radius <= 0.5)) throw new Error("obstacle radius: 0.5 to 50 cm");
    return { name, radius };
  }

  function frameInputs() {
    const name = $("frame-name").value.trim();
    const angle = (Number($("frame-angle").value) * Math.PI) / 180;
    if (!/^[A-Za-z0-9][A-Za-z0-9_-]*$/.test(name) || name.length > 40) {
      throw new Error("task frame name: a plain name (letters, digits, '_', '-')");
    }
    if (!Number.isFinite(angle)) throw new Error("task frame: turned by a number of degrees");
    return { name, angle };
  }
  function hitFrame(world) {
    for (let i = state.frames.length - 1; i >= 0; i--) {
      if (distPx(world, [state.frames[i].x, state.frames[i].y]) <= 10) return state.frames[i];
    }
    return null;
  }

  function hitObstacle(list, world) {
    for (let i = list.length - 1; i >= 0; i--) {
      const o = list[i];
      if (o.shape === "box") {
        // In the box's frame: within its half edges (and radius) plus 6 px.
        const c = Math.cos(o.yaw || 0), s = Math.sin(o.yaw || 0);
        const dx = world[0] - o.x, dy = world[1] - o.y;
        const slack = o.radius + 6 / pxPerMetre();
        if (Math.abs(c * dx + s * dy) <= o.width / 2 + slack && Math.abs(-s * dx + c * dy) <= o.depth / 2 + slack) return o;
      } else if (distPx(world, [o.x, o.y]) <= Math.max(o.radius * pxPerMetre(), 3) + 6) return o;
    }
    return null;
  }

  // ------------------------------------------------------------ pointer
  function onPointerDown(ev) {
    if (ev.button !== undefined && ev.button > 0) return;
    clearMessage();
    const world = eventWorld(ev);
    if (state.mode === "try") {
      if (!state.layers) return;
      // The nearest handle under the pointer: S, G or a task frame's origin (a frame
      // often stands where the path starts or ends).
      let target = null, nearest = Infinity;
      const handles = [[state.trial.start, 12, { kind: "start" }], [state.trial.goal, 12, { kind: "goal" }]];
      if (state.layers.task_frames && state.show.frames) {
        (state.trial.frames || []).forEach((f) => handles.push([[f.x, f.y], 10, { kind: "trialframe", item: f, grab: [f.x - world[0], f.y - world[1]] }]));
      }
      handles.forEach(([point, reach, candidate]) => {
        const d = distPx(world, point);
        if (d < reach && d < nearest) { nearest = d; target = candidate; }
      });
      if (target && target.kind === "trialframe") {
        state.selected = { kind: "trialframe", id: target.item.name };
        $("try-frame").value = target.item.name;
        showFrameAngle();
      } else if (!target) {
        const o = hitObstacle(state.trial.obstacles, world);
        if (o) {
          target = { kind: "trial", item: o, grab: [o.x - world[0], o.y - world[1]] };
          state.selected = { kind: "trial", id: o.id };
          $("try-radius").value = round(o.radius * 100, 1);
        }
      }
      if (!target) return;
      snapshot();
      state.drag = target;
      safeCapture(ev.pointerId);
      ev.preventDefault();
      return;
    }
    if (state.tool === "frame") {
      const hit = hitFrame(world);
      snapshot();
      let f = hit;
      if (f) {
        $("frame-name").value = f.name;
        $("frame-angle").value = round((f.angle * 180) / Math.PI, 0);
      } else {
        let inputs;
        try { inputs = frameInputs(); } catch (err) { state.undo.pop(); fail(err); return; }
        f = state.frames.find((x) => x.name === inputs.name);
        if (f) Object.assign(f, { x: world[0], y: world[1], angle: inputs.angle });
        else if (state.frames.length >= state.limits.max_frames) {
          state.undo.pop();
          fail(new Error(`at most ${state.limits.max_frames} task frames`));
          return;
        } else {
          f = { name: inputs.name, x: world[0], y: world[1], angle: inputs.angle };
          state.frames.push(f);
        }
      }
      state.selected = { kind: "frame", id: f.name };
      state.drag = { kind: "frame", item: f, grab: hit ? [f.x - world[0], f.y - world[1]] : [0, 0] };
      safeCapture(ev.pointerId);
      refresh();
      ev.preventDefault();
      return;
    }
    if (state.tool === "obstacle") {
      const hit = hitObstacle(state.obstacles, world);
      snapshot();
      if (hit) {
        state.selected = { kind: "obstacle", id: hit.id };
        // Where it was grabbed stays under the pointer (a box is grabbed anywhere on it).
        state.drag = { kind: "obstacle", item: hit, grab: [hit.x - world[0], hit.y - world[1]] };
        if (hit.shape === "box") { // its size in the inputs, to be changed there
          $("obstacle-shape").value = "box";
          $("box-width").value = round(hit.width * 100, 1);
          $("box-depth").value = round(hit.depth * 100, 1);
          $("box-yaw").value = round(((hit.yaw || 0) * 180) / Math.PI, 0);
        }
      } else {
        let inputs;
        try { inputs = obstacleInputs(); } catch (err) { state.undo.pop(); fail(err); return; }
        if (state.obstacles.length >= state.limits.max_obstacles) {
          state.undo.pop();
          fail(new Error(`at most ${state.limits.max_obstacles} obstacles`));
          return;
        }
        const o = { id: newObstacleId(state.obstacles), class: inputs.name, x: world[0], y: world[1], radius: inputs.radius, table: true };
        if (inputs.shape === "box") Object.assign(o, { shape: "box", width: inputs.width, depth: inputs.depth, yaw: inputs.yaw });
        state.obstacles.push(o);
        state.selected = { kind: "obstacle", id: o.id };
        state.drag = { kind: "obstacle", item: o };
      }
      safeCapture(ev.pointerId);
      refresh();
      ev.preventDefault();
      return;
    }
    // Draw a demonstration: positions with the event's time (performance.now's clock).
    state.stroke = { points: [world], stamps: [ev.timeStamp], pointer: ev.pointerId };
    safeCapture(ev.pointerId);
    ev.preventDefault();
  }

  function safeCapture(pointerId) {
    try { canvas.setPointerCapture(pointerId); } catch (err) { /* synthetic pointers */ }
  }

  function onPointerMove(ev) {
    if (state.stroke) {
      const events = ev.getCoalescedEvents ? ev.getCoalescedEvents() : [];
      for (const e of events.length ? events : [ev]) addStrokePoint(eventWorld(e), e.timeStamp || ev.timeStamp);
      draw();
      return;
    }
    if (!state.drag) return;
    const world = eventWorld(ev);
    const d = state.drag;
    if (d.kind === "start") state.trial.start = world;
    else if (d.kind === "goal") state.trial.goal = world;
    else {
      const [gx, gy] = d.grab || [0, 0];
      d.item.x = world[0] + gx; d.item.y = world[1] + gy;
    }
    if (d.kind === "trialframe") requestFramePlan(); // the obstacle plan does not see frames
    else if (state.mode === "try") requestPlan(false);
    draw();
  }

  function addStrokePoint(world, stamp) {
    const s = state.stroke;
    const last = s.points[s.points.length - 1];
    if (stamp <= s.stamps[s.stamps.length - 1]) return; // times must increase
    if (distPx(world, last) < MIN_STEP_PX) return;
    s.points.push(world);
    s.stamps.push(stamp);
  }

  function onPointerUp(ev) {
    if (state.stroke) {
      const s = state.stroke;
      if (ev.type === "pointerup") addStrokePoint(eventWorld(ev), ev.timeStamp);
      state.stroke = null;
      const length = s.points.slice(1).reduce((sum, p, i) => sum + distPx(p, s.points[i]), 0);
      if (s.points.length < MIN_POINTS || length < 15) {
        showMessage("stroke too short to be a demonstration (draw from start to goal)", "info");
        draw();
        return;
      }
      if (state.demos.length >= state.limits.max_demos) {
        fail(new Error(`at most ${state.limits.max_demos} demonstrations`));
        return;
      }
      snapshot();
      const t0 = s.stamps[0];
      state.demos.push({
        id: newDemoId(),
        points: s.points.map((p) => [p[0], p[1]]),
        times: s.stamps.map((t) => (t - t0) / 1000),
        obstacles: state.obstacles.filter((o) => o.table).map((o) => o.id),
        frames: state.frames.length ? Object.fromEntries(state.frames.map((f) => [f.name, [f.x, f.y, f.angle]])) : null,
      });
      refresh();
      return;
    }
    if (state.drag) {
      const kind = state.drag.kind;
      state.drag = null;
      if (kind === "trialframe") { requestFramePlan(); draw(); }
      else if (state.mode === "try") requestPlan(true);
      else refresh();
    }
  }

  // ------------------------------------------------------------ learn & plan
  function drawing() {
    return {
      demos: state.demos.map((d) => ({ id: d.id, points: d.points, times: d.times, obstacles: d.obstacles, frames: d.frames || null })),
      obstacles: state.obstacles.map(obstacleJson),
      params: { mimic: $("mimic").value },
    };
  }

  async function learn() {
    clearMessage();
    state.learning = true;
    renderStatus();
    $("learn-log").textContent = "sending the demonstrations…";
    try {
      await apiJson("POST", "/api/learn", drawing());
      let status;
      for (;;) {
        await new Promise((r) => setTimeout(r, 300));
        status = await apiJson("GET", "/api/learn");
        const log = $("learn-log");
        log.textContent = status.lines.join("\n") + (status.state === "running" ? `\n… ${round(status.elapsed, 1)} s` : "");
        log.scrollTop = log.scrollHeight;
        if (status.state !== "running") break;
      }
      if (status.state === "failed") throw new Error(`learning failed: ${status.error}`);
      if (status.warnings && status.warnings.length) showMessage(status.warnings.join(" · "), "info");
      learned(status.layers);
    } catch (err) {
      fail(err);
    } finally {
      state.learning = false;
      renderStatus();
    }
  }

  function learned(layers) {
    state.layers = layers;
    const path = layers.path;
    const classes = layers.classes.map((c) => c.name);
    state.trial = {
      start: path[0].slice(),
      goal: path[path.length - 1].slice(),
      obstacles: state.obstacles
        .filter((o) => o.table && classes.includes(o.class))
        .map(obstacleJson),
      frames: trialFrames(layers.task_frames),
    };
    state.plan = null;
    state.heat = null;
    state.heatImage = null;
    state.framePlan = null;
    state.framePlanError = null;
    renderClasses();
    renderFrameSelect();
    setMode("try");
    requestPlan(true);
    requestFramePlan();
  }

  // The frames to try a task-frame skill with: where they stand on the table, else where
  // the last demonstration recorded them.
  function trialFrames(learnedFrames) {
    if (!learnedFrames) return [];
    return learnedFrames.frames.map((name) => {
      const table = state.frames.find((f) => f.name === name);
      const [x, y, angle] = learnedFrames.poses[name];
      return table ? { name, x: table.x, y: table.y, angle: table.angle } : { name, x, y, angle };
    });
  }

  function renderFrameSelect() {
    const select = $("try-frame");
    select.replaceChildren();
    (state.trial.frames || []).forEach((f) => select.append(el("option", { value: f.name }, `⊹ ${f.name}`)));
    showFrameAngle();
  }
  function showFrameAngle() {
    const f = (state.trial.frames || []).find((x) => x.name === $("try-frame").value);
    if (f) $("try-frame-angle").value = round((f.angle * 180) / Math.PI, 0);
  }

  function framePlanRequest() {
    return { frames: Object.fromEntries((state.trial.frames || []).map((f) => [f.name, [f.x, f.y, f.angle]])) };
  }

  // One request of a kind in flight at a time (state[busy] while it runs): calls meanwhile
  // are merged (merge(pending, arg)) into one more run when it ends, so the latest wins.
  function singleFlight(busy, run, merge) {
    let pending = null;
    return async function request(arg) {
      if (state[busy]) { pending = merge(pending, arg); return; }
      state[busy] = true;
      try {
        await run(arg);
      } finally {
        state[busy] = false;
        const again = pending;
        pending = null;
        if (again !== null) request(again);
      }
    };
  }

  // The task-frame skill's plan for the frames' poses; the latest poses win.
  const requestFramePlan = singleFlight("framePlanBusy", async () => {
    if (!state.layers || !state.layers.task_frames) return;
    try {
      state.framePlan = await apiJson("POST", "/api/plan/frames", framePlanRequest());
      state.framePlanError = null;
      state.framePlanCount++;
    } catch (err) {
      state.framePlan = null;
      state.framePlanError = err.message;
    }
    renderFramePlanInfo();
    draw();
  }, () => true);

  function planRequest(withHeat) {
    const body = {
      start: state.trial.start,
      goal: state.trial.goal,
      obstacles: state.trial.obstacles.map(obstacleJson),
    };
    if (withHeat) body.heat = { view: state.view, nx: HEAT_NX, ny: HEAT_NY };
    return body;
  }

  // The obstacle skill's plan; the latest position wins, final (with the heat map) if any
  // call meanwhile was.
  const requestPlan = singleFlight("planBusy", async (final) => {
    if (!state.layers) return;
    const sent = performance.now();
    try {
      const plan = await apiJson("POST", "/api/plan", planRequest(final && state.show.heat));
      state.roundTrip = performance.now() - sent;
      state.plan = plan;
      state.planError = null;
      if (plan.heat) { state.heat = plan.heat; state.heatImage = makeHeatImage(plan.heat); }
      state.planCount++;
    } catch (err) {
      state.plan = null;
      state.planError = err.message;
    }
    renderPlanInfo();
    refresh();
  }, (pending, final) => Boolean(pending) || Boolean(final));

  function addTrialObstacle() {
    const name = $("try-class").value;
    if (!name) return;
    if (state.trial.obstacles.length >= state.limits.max_obstacles) { fail(new Error("too many obstacles")); return; }
    snapshot();
    const path = state.plan ? state.plan.points : state.layers.path;
    const mid = path[Math.floor(path.length / 2)];
    const radius = Number($("try-radius").value) / 100;
    if (!(radius > 0 && radius <= 0.5)) { fail(new Error("obstacle radius: 0.5 to 50 cm")); return; }
    // Beside the path, for the user to drag onto it.
    const o = { id: newObstacleId(state.trial.obstacles.concat(state.obstacles)), class: name, x: mid[0], y: mid[1] + 0.15, radius };
    state.trial.obstacles.push(o);
    state.selected = { kind: "trial", id: o.id };
    requestPlan(true);
  }

  // ------------------------------------------------------------ files
  function saveBlob(blob, name) {
    const url = URL.createObjectURL(blob);
    const a = el("a", { href: url, download: name });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
  }
  async function download(method, path, body, name) {
    clearMessage();
    try {
      const response = await api(method, path, body);
      saveBlob(await response.blob(), name);
    } catch (err) { fail(err); }
  }

  // Widen the view (keeping its shape) when imported data lie outside it.
  function fitView(points) {
    if (!points.length) return;
    const [x0, x1, y0, y1] = state.view;
    if (points.every(([x, y]) => x >= x0 && x <= x1 && y >= y0 && y <= y1)) return;
    const xs = points.map((p) => p[0]), ys = points.map((p) => p[1]);
    const lo = [Math.min(...xs), Math.min(...ys)], hi = [Math.max(...xs), Math.max(...ys)];
    const aspect = (x1 - x0) / (y1 - y0);
    const width = Math.max((hi[0] - lo[0]) * 1.2, (hi[1] - lo[1]) * 1.2 * aspect, 1e-3);
    const cx = (lo[0] + hi[0]) / 2, cy = (lo[1] + hi[1]) / 2;
    state.view = [cx - width / 2, cx + width / 2, cy - width / aspect / 2, cy + width / aspect / 2];
  }
  function fitAll() {
    const points = [];
    state.demos.forEach((d) => d.points.forEach((p) => points.push(p)));
    state.obstacles.forEach((o) => points.push([o.x, o.y]));
    fitView(points);
  }

  function mergeDemos(demos) {
    snapshot();
    const renamed = [];
    demos.forEach((d) => {
      let id = d.id;
      if (state.demos.some((x) => x.id === id) || !/^[A-Za-z0-9][A-Za-z0-9_.-]*$/.test(id)) {
        id = newDemoId();
        renamed.push(d.id);
      }
      state.demos.push({ id, points: d.points, times: d.times, obstacles: [], frames: d.frames || null });
    });
    return renamed;
  }

  function mergeScenes(scenes) {
    const ids = {};
    scenes.obstacles.forEach((o) => {
      const id = newObstacleId(state.obstacles);
      ids[o.id] = id;
      // Obstacles of recorded scenes: not on the table for new strokes.
      state.obstacles.push({ ...obstacleJson(o), id, table: false });
    });
    const missing = [];
    Object.entries(scenes.marks).forEach(([demo, marks]) => {
      const d = state.demos.find((x) => x.id === demo);
      if (!d) { missing.push(demo); return; }
      d.obstacles = Array.from(new Set(d.obstacles.concat(marks.map((m) => ids[m]))));
    });
    return missing;
  }

  async function importFile(kind, input) {
    clearMessage();
    const file = input.files && input.files[0];
    input.value = "";
    if (!file) return;
    const ext = (file.name.split(".").pop() || "").toLowerCase();
    try {
      if (file.size > state.limits.max_body_bytes) throw new Error(`${file.name}: larger than ${state.limits.max_body_bytes / 1e6} MB`);
      const bytes = await file.arrayBuffer();
      const data = await (await api("POST", `/api/import/${kind}?format=${encodeURIComponent(ext)}`, undefined, bytes)).json();
      if (kind === "demos") {
        if (state.demos.length + data.demos.length > state.limits.max_demos) throw new Error(`at most ${state.limits.max_demos} demonstrations`);
        const renamed = mergeDemos(data.demos);
        fitAll();
        showMessage(`${file.name}: ${data.demos.length} demonstrations` + (renamed.length ? ` (renamed: ${renamed.join(", ")})` : ""), "info");
      } else {
        snapshot();
        const missing = mergeScenes(data);
        fitAll();
        showMessage(`${file.name}: ${data.obstacles.length} obstacles` + (missing.length ? `; no demonstration ${missing.join(", ")} to mark` : ""), missing.length ? "error" : "info");
      }
      refresh();
    } catch (err) { fail(err); }
  }

  async function loadExample() {
    clearMessage();
    try {
      const data = await apiJson("GET", "/api/example");
      snapshot();
      state.demos = [];
      state.obstacles = [];
      mergeDemos(data.demos);
      state.undo.pop();
      mergeScenes(data);
      showMessage(`the sweeping example: ${data.demos.length} demonstrations, ${data.obstacles.length} recorded obstacles (off the table)`, "info");
      setMode("teach");
    } catch (err) { fail(err); }
  }

  function setMode(mode) {
    if (mode === "try" && !state.layers) return;
    state.mode = mode;
    state.selected = null;
    refresh();
    if (mode === "try") { renderClasses(); renderPlanInfo(); renderFramePlanInfo(); }
  }

  // ------------------------------------------------------------ start
  function bind() {
    canvas.addEventListener("pointerdown", onPointerDown);
    canvas.addEventListener("pointermove", onPointerMove);
    canvas.addEventListener("pointerup", onPointerUp);
    canvas.addEventListener("pointercancel", onPointerUp);
    document.querySelectorAll('input[name="tool"]').forEach((r) => {
      r.onchange = () => { state.tool = r.value; renderStatus(); };
    });
    document.querySelectorAll("#modes button").forEach((b) => { b.onclick = () => setMode(b.dataset.mode); });
    document.querySelectorAll("[data-layer]").forEach((box) => {
      box.onchange = () => {
        state.show[box.dataset.layer] = box.checked;
        if (box.dataset.layer === "heat" && box.checked) requestPlan(true);
        if (box.dataset.layer === "frames") renderFramePlanInfo();
        draw();
      };
    });
    $("message-close").onclick = clearMessage;
    $("undo").onclick = undo;
    $("clear").onclick = () => {
      snapshot();
      state.demos = [];
      state.obstacles = [];
      state.frames = [];
      state.selected = null;
      state.view = state.defaultView.slice();
      refresh();
    };
    $("example").onclick = loadExample;
    $("learn").onclick = learn;
    $("add-obstacle").onclick = addTrialObstacle;
    $("import-demos").onchange = (e) => importFile("demos", e.target);
    $("import-scenes").onchange = (e) => importFile("scenes", e.target);
    $("export-demos").onclick = () => download("POST", "/api/export/demos", drawing(), "demos.csv");
    $("export-scenes").onclick = () => download("POST", "/api/export/scenes", drawing(), "scenes.csv");
    $("export-skill").onclick = () => download("GET", "/api/export/skill", undefined, "skill.json");
    $("export-frame-skill").onclick = () => download("GET", "/api/export/task-frame-skill", undefined, "task-frame-skill.json");
    $("try-frame").onchange = () => {
      state.selected = { kind: "trialframe", id: $("try-frame").value };
      showFrameAngle();
      draw();
    };
    $("try-frame-angle").onchange = () => {
      const f = (state.trial.frames || []).find((x) => x.name === $("try-frame").value);
      const angle = (Number($("try-frame-angle").value) * Math.PI) / 180;
      if (!f) return;
      if (!Number.isFinite(angle)) { fail(new Error("task frame: turned by a number of degrees")); return; }
      snapshot();
      f.angle = angle;
      requestFramePlan();
      draw();
    };
    $("export-plan").onclick = () => download("POST", "/api/export/plan", planRequest(false), "plan.csv");
    $("export-urscript").onclick = () => download("POST", "/api/export/urscript", planRequest(false), "program.script");
    $("try-radius").onchange = () => {
      const s = state.selected;
      const o = s && s.kind === "trial" && state.trial.obstacles.find((x) => x.id === s.id);
      const radius = Number($("try-radius").value) / 100;
      if (!o) return;
      if (!(radius > 0 && radius <= 0.5)) { fail(new Error("obstacle radius: 0.5 to 50 cm")); return; }
      snapshot();
      o.radius = radius;
      requestPlan(true);
    };
    ["box-width", "box-depth", "box-yaw"].forEach((key) => {
      $(key).onchange = () => {
        const s = state.selected;
        const list = s && s.kind === "obstacle" ? state.obstacles : s && s.kind === "trial" ? state.trial.obstacles : null;
        const o = list && list.find((x) => x.id === s.id);
        if (!o || o.shape !== "box") return;
        let inputs;
        try { inputs = obstacleInputs(); } catch (err) { fail(err); return; }
        if (inputs.shape !== "box") return;
        snapshot();
        Object.assign(o, { width: inputs.width, depth: inputs.depth, yaw: inputs.yaw });
        if (state.mode === "try") requestPlan(true); else refresh();
      };
    });
    $("frame-angle").onchange = () => {
      const s = state.selected;
      const f = s && s.kind === "frame" && state.frames.find((x) => x.name === s.id);
      if (!f) return;
      let inputs;
      try { inputs = frameInputs(); } catch (err) { fail(err); return; }
      snapshot();
      f.angle = inputs.angle;
      refresh();
    };
    $("obstacle-radius").onchange = () => {
      const s = state.selected;
      const list = s && s.kind === "obstacle" ? state.obstacles : s && s.kind === "trial" ? state.trial.obstacles : null;
      const o = list && list.find((x) => x.id === s.id);
      if (!o || o.shape === "box") return; // a box's size is set by its own inputs
      try { const { radius } = obstacleInputs(); snapshot(); o.radius = radius; } catch (err) { fail(err); return; }
      if (state.mode === "try") requestPlan(true); else refresh();
    };
    document.addEventListener("keydown", (ev) => {
      if (ev.target && ["INPUT", "SELECT", "TEXTAREA"].includes(ev.target.tagName)) return;
      if ((ev.ctrlKey || ev.metaKey) && ev.key === "z") { ev.preventDefault(); undo(); }
      else if (ev.key === "Delete" || ev.key === "Backspace") { ev.preventDefault(); deleteSelected(); }
    });
    window.addEventListener("resize", () => { if ((window.devicePixelRatio || 1) !== devicePixelRatioUsed) resize(); });
  }

  async function start() {
    bind();
    resize();
    try {
      const info = await apiJson("POST", "/api/session");
      state.session = info.session;
      state.limits = info.limits;
      state.view = info.view;
      state.defaultView = info.view.slice();
      refresh();
      document.body.dataset.ready = "yes";
    } catch (err) {
      fail(err);
      $("status").textContent = "not connected";
    }
  }

  // For tests and the curious: the page's state and its API calls.
  window.lfdkitTeach = {
    state, api, apiJson, requestPlan, requestFramePlan, setMode, toPx, toWorld, drawing, planRequest,
    framePlanRequest, refresh,
  };
  start();
})();
