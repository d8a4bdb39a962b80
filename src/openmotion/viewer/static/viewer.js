// openmotion view: draws the frames the server streams over /ws. No libraries, and nothing is
// fetched but this page's own files and socket, so the viewer works offline.
//
// Messages in: {type: "hello"} once per machine (its name, the signals), {type: "scope"} with
// the scope samples this page has not seen (reset: a new selection), {type: "frame"} at the
// session's frame rate (fewer while the machine is late: frame.notice says so in plain
// words), {type: "error"} when a control was refused. Messages out: the
// controls, {op: "play" | "pause" | "step" | "restart" | "speed" | "scope", ...}.
// Each panel kind of a frame ("axes", "rail", "planar") has a height and a draw function
// below; a new kind of layer needs both here.
"use strict";

const PALETTE = ["#2f6fb3", "#e07b39", "#3a9d5d", "#b8479b", "#c9a227", "#4aa3b5", "#7d5cc6",
  "#c94f4f", "#5b7d2e", "#8a6d3b"];
const INK = "#1d2733";
const MUTED = "#6b7684";
const BAD = "#c63b3b";
const GOOD = "#3a9d5d";
const WARN = "#d9a03a";
const IDLE = "#9aa3ad";
const SCOPE_WINDOW = 10; // seconds of virtual time the scope shows at most
const SCOPE_HEIGHT = 220;
const SCOPE_LIMIT = 6; // the session's SCOPE_SIGNALS
const TITLE = 22; // height of a panel's title line
const PICKER_LIMIT = 400; // signal check boxes shown at once
const COLUMNS = ["kind", "name", "state", "position", "velocity", "command", "detail"]; // and
// the error, on a line of its own
const UNITS = {set_position: "mm", position: "mm", x: "mm", y: "mm", z: "mm", gap: "mm",
  following_error: "mm lag", set_velocity: "mm/s", velocity: "mm/s", set_acceleration: "mm/s²",
  c: "°"}; // signals of one unit share a scale

const view = {
  hello: null,
  frame: null,
  pending: false,
  scopeNames: [],
  samples: [],
  extents: new Map(), // grown bounds of the drawings, so that the view does not jump
  rows: new Map(), // table rows by kind/name
  colours: new Map(), // a stable colour per object name
};

const $ = (id) => document.getElementById(id);

// -- connection ---------------------------------------------------------------------------

let socket = null;

function connect() {
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  socket = new WebSocket(`${scheme}://${location.host}/ws`);
  socket.addEventListener("message", (event) => receive(JSON.parse(event.data)));
  socket.addEventListener("close", () => {
    setBadge("disconnected", "");
    setTimeout(connect, 1000);
  });
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) {
    socket.send(JSON.stringify(message));
  }
}

function receive(message) {
  if (message.type === "hello") {
    view.hello = message;
    view.extents.clear();
    view.colours.clear();
    buildPicker();
    $("restart").disabled = !message.restart;
  } else if (message.type === "scope") {
    if (message.reset) {
      setScope(message.names, message.samples);
      buildPicker();
    } else {
      addSamples(message.samples);
    }
  } else if (message.type === "frame") {
    view.frame = message;
    requestRender();
  } else if (message.type === "error") {
    $("failure").textContent = message.message;
  }
}

function requestRender() {
  if (!view.pending) {
    view.pending = true;
    requestAnimationFrame(render);
  }
}

function render() {
  view.pending = false;
  const frame = view.frame;
  if (!frame) {
    return;
  }
  renderStatus(frame);
  drawMachine(frame);
  drawScope();
  renderLegend();
  renderTable(frame);
}

// -- status and controls ------------------------------------------------------------------

function setBadge(text, kind) {
  const badge = $("status");
  badge.textContent = text;
  badge.className = `badge ${kind}`;
}

function renderStatus(frame) {
  $("name").textContent = frame.name;
  $("time").textContent = frame.time.toFixed(3);
  $("cycle").textContent = `cycle ${frame.cycle}`;
  const status = frame.finished ? (frame.failure ? "stopped" : "finished")
    : frame.waiting ? "waiting" : frame.paused ? "paused" : frame.behind ? "behind" : "running";
  setBadge(status === "waiting" ? "waiting for a page" : status,
    status === "stopped" ? "behind" : status);
  const running = !(frame.paused || frame.finished || frame.waiting);
  let rate = running && frame.rate !== null
    ? `${frame.speed}× asked, ${frame.rate.toFixed(2)}× running` : `${frame.speed}×`;
  if (running && view.hello && frame.frame_rate < view.hello.frame_rate) {
    rate += ` · ${Number(frame.frame_rate.toFixed(2))} frames/s`; // frames dropped
  }
  $("rate").textContent = rate;
  $("notice").textContent = frame.notice;
  $("toggle").textContent = frame.paused ? "Play" : "Pause";
  $("toggle").disabled = frame.finished;
  $("step").disabled = frame.finished;
  $("failure").textContent = frame.failure;
  const speed = $("speed");
  if (document.activeElement !== speed) {
    const value = String(frame.speed);
    if (![...speed.options].some((option) => option.value === value)) {
      speed.add(new Option(`${value}×`, value));
    }
    speed.value = value;
  }
}

function bindControls() {
  $("toggle").addEventListener("click", () => {
    send({op: view.frame && view.frame.paused ? "play" : "pause"});
  });
  $("step").addEventListener("click", () => send({op: "step"}));
  $("restart").addEventListener("click", () => send({op: "restart"}));
  $("speed").addEventListener("change", (event) => {
    send({op: "speed", value: Number(event.target.value)});
    event.target.blur();
  });
  $("filter").addEventListener("input", buildPicker);
  document.addEventListener("keydown", (event) => {
    if (["INPUT", "SELECT", "BUTTON"].includes(event.target.tagName)) {
      return;
    }
    if (event.key === " ") {
      event.preventDefault();
      $("toggle").click();
    } else if (event.key === ".") {
      $("step").click();
    }
  });
  window.addEventListener("resize", requestRender);
}

// -- drawing helpers ----------------------------------------------------------------------

function fitCanvas(canvas, height) {
  const ratio = window.devicePixelRatio || 1;
  const width = canvas.clientWidth;
  const pixelsWide = Math.round(width * ratio);
  const pixelsHigh = Math.round(height * ratio);
  if (canvas.width !== pixelsWide || canvas.height !== pixelsHigh) {
    canvas.width = pixelsWide;
    canvas.height = pixelsHigh;
    canvas.style.height = `${height}px`;
  }
  const ctx = canvas.getContext("2d");
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  ctx.clearRect(0, 0, width, height);
  return ctx;
}

function grow(key, box) {
  const old = view.extents.get(key);
  const next = old ? [Math.min(old[0], box[0]), Math.min(old[1], box[1]),
    Math.max(old[2], box[2]), Math.max(old[3], box[3])] : box;
  view.extents.set(key, next);
  return next;
}

function colourOf(name) {
  if (!view.colours.has(name)) {
    view.colours.set(name, PALETTE[view.colours.size % PALETTE.length]);
  }
  return view.colours.get(name);
}

function stateColour(name, state, error) {
  if (error || state.startsWith("ERROR")) {
    return BAD;
  }
  if (state === "DISABLED") {
    return IDLE;
  }
  if (state.endsWith("ING")) {
    return WARN; // enabling, disabling, resetting
  }
  return colourOf(name);
}

function label(ctx, text, x, y, colour = INK, align = "center", font = "12px") {
  ctx.font = `${font} system-ui, sans-serif`;
  ctx.fillStyle = colour;
  ctx.textAlign = align;
  ctx.textBaseline = "middle";
  ctx.fillText(text, x, y);
}

function format(value, digits = 1) {
  return value === null || value === undefined ? "-" : value.toFixed(digits);
}

// -- the machine canvas -------------------------------------------------------------------

const PANELS = {
  axes: {height: axesHeight, draw: drawAxes},
  rail: {height: railHeight, draw: drawRail},
  planar: {height: planarHeight, draw: drawPlanar},
};

function drawMachine(frame) {
  const canvas = $("machine");
  const width = canvas.clientWidth;
  const panels = frame.panels.filter((panel) => PANELS[panel.kind]
    && !(panel.kind === "axes" && panel.axes.length === 0));
  const heights = panels.map((panel) => TITLE + PANELS[panel.kind].height(panel, width));
  const total = Math.max(120, heights.reduce((sum, height) => sum + height, 0));
  const ctx = fitCanvas(canvas, total);
  let top = 0;
  panels.forEach((panel, index) => {
    ctx.save();
    ctx.translate(0, top);
    const title = panel.kind === "axes" ? "axes"
      : panel.kind === "rail" ? `CA group ${panel.name} · ${panel.state.toLowerCase()}`
        : "planar field";
    label(ctx, title, 8, TITLE / 2, MUTED, "left");
    ctx.translate(0, TITLE);
    PANELS[panel.kind].draw(ctx, panel, width, heights[index] - TITLE);
    ctx.restore();
    top += heights[index];
  });
  if (!panels.length) {
    label(ctx, "nothing to draw: the objects are in the table", width / 2, 60, MUTED);
  }
}

// axes: one bar per axis; soft limits as the range, else the range seen so far

const AXIS_ROW = 30;

function axesHeight(panel) {
  return panel.axes.length * AXIS_ROW + 6;
}

function drawAxes(ctx, panel, width) {
  const left = 80;
  const right = width - 100;
  panel.axes.forEach((axis, index) => {
    const y = index * AXIS_ROW + AXIS_ROW / 2;
    const seen = [axis.set_position, axis.position].filter((value) => value !== null);
    let [lo, , hi] = grow(`axis:${axis.name}`, [Math.min(0, ...seen), 0, Math.max(0, ...seen), 0]);
    if (axis.min !== null && axis.max !== null) {
      [lo, hi] = [axis.min, axis.max];
    } else {
      const pad = Math.max((hi - lo) * 0.06, 1);
      [lo, hi] = [lo - pad, hi + pad];
    }
    const x = (value) => left + ((value - lo) / (hi - lo)) * (right - left);
    const colour = stateColour(axis.name, axis.state, axis.error);
    label(ctx, axis.name, 10, y, INK, "left", "600 12px");
    ctx.fillStyle = "#e6eaf0";
    ctx.fillRect(left, y - 4, right - left, 8);
    if (lo < 0 && hi > 0) {
      ctx.fillStyle = "#b8c0cb";
      ctx.fillRect(x(0) - 0.5, y - 8, 1, 16);
    }
    if (axis.set_position !== null) {
      ctx.strokeStyle = colour;
      ctx.lineWidth = 2;
      ctx.strokeRect(x(axis.set_position) - 5, y - 9, 10, 18);
    }
    if (axis.position !== null) {
      ctx.fillStyle = colour;
      ctx.beginPath();
      ctx.arc(x(axis.position), y, 5, 0, 2 * Math.PI);
      ctx.fill();
    }
    label(ctx, `${format(axis.set_position, 3)}`, right + 12, y, INK, "left");
    label(ctx, `${format(lo, 0)}`, left, y + 12, MUTED, "left", "10px");
    label(ctx, `${format(hi, 0)}`, right, y + 12, MUTED, "right", "10px");
  });
}

// rail: a ring is drawn as a stadium, 1/3 of the length per straight (the XTS starter kit);
// positions run clockwise from the left end of the upper straight

const RING_ASPECT = (1 / 3 + 1 / (3 * Math.PI)) / (1 / (3 * Math.PI)); // width : height
const RING_PAD = [56, 48]; // room for the labels outside the ring [px]

function railHeight(panel, width) {
  if (!panel.ring) {
    return 100;
  }
  const inner = (width - 2 * RING_PAD[0]) / RING_ASPECT;
  return Math.min(Math.max(inner, 60), 300) + 2 * RING_PAD[1];
}

function ringPath(length, width, height) {
  const straight = length / 3;
  const radius = length / (6 * Math.PI);
  const scale = Math.min((width - 2 * RING_PAD[0]) / (straight + 2 * radius),
    (height - 2 * RING_PAD[1]) / (2 * radius));
  const ox = (width - (straight + 2 * radius) * scale) / 2;
  const oy = (height - 2 * radius * scale) / 2;
  const arc = Math.PI * radius;
  return (position) => {
    const p = ((position % length) + length) % length;
    let x, y, angle;
    if (p < straight) {
      [x, y, angle] = [radius + p, 0, 0];
    } else if (p < straight + arc) {
      const turn = (p - straight) / radius;
      [x, y, angle] = [radius + straight + radius * Math.sin(turn),
        radius - radius * Math.cos(turn), turn];
    } else if (p < 2 * straight + arc) {
      [x, y, angle] = [radius + straight - (p - straight - arc), 2 * radius, Math.PI];
    } else {
      const turn = (p - 2 * straight - arc) / radius;
      [x, y, angle] = [radius - radius * Math.sin(turn), radius + radius * Math.cos(turn),
        Math.PI + turn];
    }
    return [ox + x * scale, oy + y * scale, angle];
  };
}

function linePath(length, width, height) {
  const pad = 40;
  return (position) => {
    const p = Math.min(Math.max(position, 0), length);
    return [pad + (p / length) * (width - 2 * pad), height / 2, 0];
  };
}

function strokeAlong(ctx, path, from, to, offset = 0) {
  const steps = Math.max(2, Math.ceil(Math.abs(to - from) / 10));
  ctx.beginPath();
  for (let i = 0; i <= Math.min(steps, 400); i += 1) {
    const [x, y, angle] = path(from + ((to - from) * i) / Math.min(steps, 400));
    const [nx, ny] = [Math.sin(angle) * offset, -Math.cos(angle) * offset];
    if (i === 0) {
      ctx.moveTo(x + nx, y + ny);
    } else {
      ctx.lineTo(x + nx, y + ny);
    }
  }
  ctx.stroke();
}

function drawRail(ctx, panel, width, height) {
  const length = panel.length;
  const path = panel.ring ? ringPath(length, width, height) : linePath(length, width, height);
  ctx.lineCap = "round";
  ctx.strokeStyle = "#d3d9e1";
  ctx.lineWidth = 12;
  strokeAlong(ctx, path, 0, length);
  panel.parts.forEach((part, index) => {
    const end = panel.ring && part.end <= part.start ? part.end + length : part.end;
    ctx.strokeStyle = index % 2 ? "#9fb7d4" : "#c7b48f";
    ctx.lineWidth = 3;
    strokeAlong(ctx, path, part.start, end, 14);
    const [x, y, angle] = path((part.start + end) / 2);
    label(ctx, `part ${part.id}`, x + Math.sin(angle) * 26, y - Math.cos(angle) * 26, MUTED,
      "center", "10px");
  });
  for (const station of panel.stations || []) {
    station.slots.forEach((position, slot) => {
      const [x, y, angle] = path(position);
      ctx.strokeStyle = MUTED;
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.moveTo(x - Math.sin(angle) * 12, y + Math.cos(angle) * 12);
      ctx.lineTo(x - Math.sin(angle) * 22, y + Math.cos(angle) * 22);
      ctx.stroke();
      if (slot === 0) {
        const queue = station.queue ? ` · queue ${station.queue}` : "";
        label(ctx, `${station.name} (${station.processed})${queue}`,
          x - Math.sin(angle) * 32, y + Math.cos(angle) * 32, MUTED, "center", "10px");
      }
    });
  }
  for (const mover of panel.movers) {
    const wanted = mover.wanted_gap || 0;
    if (mover.gap === null || mover.position === null || mover.gap > 2 * wanted) {
      continue; // only gaps near the one to keep are drawn
    }
    const short = mover.gap < wanted - 1e-6;
    ctx.strokeStyle = short ? BAD : mover.gap < 1.2 * wanted ? WARN : GOOD;
    ctx.lineWidth = 3;
    ctx.lineCap = "butt";
    strokeAlong(ctx, path, mover.position, mover.position + mover.gap);
    const [xa, ya] = path(mover.position);
    const [xb, yb] = path(mover.position + mover.gap);
    if (Math.hypot(xb - xa, yb - ya) > 44) {
      const [x, y, angle] = path(mover.position + mover.gap / 2);
      label(ctx, format(mover.gap, 0), x - Math.sin(angle) * 17, y + Math.cos(angle) * 17,
        ctx.strokeStyle, "center", "10px");
    }
  }
  for (const mover of panel.movers) {
    if (mover.position === null) {
      continue;
    }
    const [x, y, angle] = path(mover.position);
    ctx.save();
    ctx.translate(x, y);
    ctx.rotate(angle);
    ctx.fillStyle = mover.error ? BAD : colourOf(mover.name);
    ctx.fillRect(-11, -8, 22, 16);
    ctx.restore();
    label(ctx, mover.name, x + Math.sin(angle) * 40, y - Math.cos(angle) * 40, INK, "center",
      "600 11px");
  }
}

// planar: world y points up; the bounds grow with what was seen

function planarBounds(panel) {
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  const add = (x, y) => {
    box[0] = Math.min(box[0], x);
    box[1] = Math.min(box[1], y);
    box[2] = Math.max(box[2], x);
    box[3] = Math.max(box[3], y);
  };
  for (const [x, y] of panel.stators) {
    add(x, y);
    add(x + panel.stator_size, y + panel.stator_size);
  }
  for (const part of panel.parts) {
    part.rings.forEach((ring) => ring.forEach(([x, y]) => add(x, y)));
  }
  for (const mover of panel.movers) {
    const reach = 0.75 * Math.max(mover.width, mover.height);
    add(mover.x - reach, mover.y - reach);
    add(mover.x + reach, mover.y + reach);
  }
  if (box[0] === Infinity) {
    return [0, 0, 960, 960];
  }
  const margin = 20;
  return grow(`planar:${panel.name}`, [box[0] - margin, box[1] - margin, box[2] + margin,
    box[3] + margin]);
}

function planarHeight(panel, width) {
  const [x0, y0, x1, y1] = planarBounds(panel);
  return Math.min(Math.max((width * (y1 - y0)) / (x1 - x0), 180), 620);
}

function tracePolygon(ctx, rings, X, Y) {
  ctx.beginPath();
  for (const ring of rings) {
    ring.forEach(([x, y], index) => (index ? ctx.lineTo(X(x), Y(y)) : ctx.moveTo(X(x), Y(y))));
    ctx.closePath();
  }
}

function drawPlanar(ctx, panel, width, height) {
  const [x0, y0, x1, y1] = planarBounds(panel);
  const pad = 10;
  const scale = Math.min((width - 2 * pad) / (x1 - x0), (height - 2 * pad) / (y1 - y0));
  const ox = (width - (x1 - x0) * scale) / 2;
  const oy = (height - (y1 - y0) * scale) / 2;
  const X = (x) => ox + (x - x0) * scale;
  const Y = (y) => oy + (y1 - y) * scale;
  const size = panel.stator_size * scale;
  ctx.lineWidth = 1;
  for (const [x, y] of panel.stators) {
    ctx.fillStyle = "#eef1f5";
    ctx.fillRect(X(x), Y(y + panel.stator_size), size, size);
    ctx.strokeStyle = "#c9d0da";
    ctx.strokeRect(X(x) + 0.5, Y(y + panel.stator_size) + 0.5, size - 1, size - 1);
  }
  for (const part of panel.parts) {
    tracePolygon(ctx, part.rings, X, Y);
    ctx.strokeStyle = stateColour(part.name, part.state, false);
    ctx.lineWidth = 2;
    ctx.stroke();
  }
  const polyline = (points) => {
    ctx.beginPath();
    points.forEach(([x, y], index) => (index ? ctx.lineTo(X(x), Y(y))
      : ctx.moveTo(X(x), Y(y))));
  };
  for (const track of panel.tracks || []) {
    polyline(track.points);
    ctx.strokeStyle = track.mode === "MOVING" ? "#5b6b80" : "#8a94a3";
    ctx.lineWidth = 2;
    ctx.stroke();
    for (const range of track.ranges || []) { // collision ranges at switches (§6.2.2)
      polyline(range);
      ctx.strokeStyle = "rgba(230, 140, 40, 0.55)";
      ctx.lineWidth = 6;
      ctx.stroke();
    }
  }
  for (const [x, y] of panel.switches || []) {
    ctx.beginPath();
    ctx.arc(X(x), Y(y), 4, 0, 2 * Math.PI);
    ctx.fillStyle = "#d06a1a";
    ctx.fill();
  }
  for (const obstacle of panel.obstacles || []) { // a router's static obstacles
    tracePolygon(ctx, obstacle.rings, X, Y);
    ctx.fillStyle = "#c4c9d1";
    ctx.fill("evenodd");
    ctx.strokeStyle = "#6b7480";
    ctx.lineWidth = 1;
    ctx.stroke();
    label(ctx, obstacle.name, X(obstacle.rings[0][0][0]) + 3, Y(obstacle.rings[0][0][1]) - 7,
      "#3d4450", "left", "10px");
  }
  for (const route of panel.routes || []) { // planned ways of movers still on them
    polyline(route.points);
    ctx.strokeStyle = colourOf(route.mover);
    ctx.globalAlpha = 0.8;
    ctx.setLineDash([6, 4]);
    ctx.lineWidth = 2;
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }
  for (const area of panel.reserved) {
    const colour = colourOf(area.mover);
    tracePolygon(ctx, area.rings, X, Y);
    ctx.globalAlpha = 0.16;
    ctx.fillStyle = colour;
    ctx.fill("evenodd");
    ctx.globalAlpha = 0.7;
    ctx.setLineDash([4, 3]);
    ctx.strokeStyle = colour;
    ctx.lineWidth = 1;
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }
  for (const mover of panel.movers) {
    const w = mover.width * scale;
    const h = mover.height * scale;
    ctx.save();
    ctx.translate(X(mover.x), Y(mover.y));
    ctx.rotate((-mover.c * Math.PI) / 180);
    if (mover.z > 0) {
      ctx.shadowColor = "rgba(0, 0, 0, 0.35)";
      ctx.shadowBlur = 4 + mover.z * 2;
      ctx.shadowOffsetY = 2 + mover.z;
    }
    ctx.fillStyle = stateColour(mover.name, mover.state, mover.error);
    ctx.fillRect(-w / 2, -h / 2, w, h);
    ctx.shadowColor = "transparent";
    ctx.fillStyle = "rgba(255, 255, 255, 0.85)"; // a notch on the mover's +x side shows C
    ctx.beginPath();
    ctx.moveTo(w / 2 - 2, 0);
    ctx.lineTo(w / 2 - 2 - Math.min(10, w / 5), -Math.min(6, h / 8));
    ctx.lineTo(w / 2 - 2 - Math.min(10, w / 5), Math.min(6, h / 8));
    ctx.closePath();
    ctx.fill();
    ctx.restore();
    label(ctx, mover.name, X(mover.x), Y(mover.y), "#ffffff", "center", "600 12px");
  }
}

// -- the scope ----------------------------------------------------------------------------

function setScope(names, samples) {
  view.scopeNames = names.slice();
  view.samples = [];
  addSamples(samples);
}

function addSamples(samples) {
  const last = view.samples.length ? view.samples[view.samples.length - 1][0] : -Infinity;
  for (const sample of samples) {
    if (sample[0] > last || view.samples.length === 0) {
      view.samples.push(sample);
    }
  }
  const end = view.samples.length ? view.samples[view.samples.length - 1][0] : 0;
  const first = view.samples.findIndex((sample) => sample[0] >= end - SCOPE_WINDOW);
  if (first > 0) {
    view.samples.splice(0, first);
  }
}

function unitOf(name) {
  const property = name.slice(name.lastIndexOf(".") + 1);
  return UNITS[property] || property;
}

function scopeRanges(samples) {
  const ranges = new Map();
  view.scopeNames.forEach((name, index) => {
    const range = ranges.get(unitOf(name)) || [Infinity, -Infinity];
    for (const sample of samples) {
      const value = sample[index + 1];
      if (value !== null) {
        range[0] = Math.min(range[0], value);
        range[1] = Math.max(range[1], value);
      }
    }
    ranges.set(unitOf(name), range);
  });
  for (const [unit, [lo, hi]] of ranges) {
    const [low, high] = lo === Infinity ? [-1, 1] : hi - lo < 1e-9 ? [lo - 1, hi + 1] : [lo, hi];
    const pad = (high - low) * 0.06;
    ranges.set(unit, [low - pad, high + pad]);
  }
  return ranges;
}

// one vertical scale per unit: signals of one unit share it; the first unit's scale is on the
// left, the second's on the right
function drawScope() {
  const ctx = fitCanvas($("scope"), SCOPE_HEIGHT);
  const width = $("scope").clientWidth;
  const samples = view.samples;
  const ranges = scopeRanges(samples);
  const units = [...ranges.keys()];
  const [left, right, top, bottom] = [58, width - (units.length > 1 ? 58 : 10), 16,
    SCOPE_HEIGHT - 22];
  const end = samples.length ? samples[samples.length - 1][0] : 0;
  const span = Math.min(SCOPE_WINDOW, Math.max(2, Math.ceil(end))); // grows, then slides
  const t0 = Math.max(0, end - span);
  const t1 = t0 + span;
  const tick = span <= 4 ? 0.5 : 1;
  const X = (t) => left + ((t - t0) / (t1 - t0)) * (right - left);
  const Y = (value, [lo, hi]) => bottom - ((value - lo) / (hi - lo)) * (bottom - top);
  ctx.lineWidth = 1;
  for (let i = 0; i <= 4; i += 1) {
    const y = bottom - ((bottom - top) * i) / 4;
    ctx.strokeStyle = "#edf0f4";
    ctx.beginPath();
    ctx.moveTo(left, y);
    ctx.lineTo(right, y);
    ctx.stroke();
    units.slice(0, 2).forEach((unit, side) => {
      const [lo, hi] = ranges.get(unit);
      label(ctx, (lo + ((hi - lo) * i) / 4).toPrecision(4), side ? right + 6 : left - 6, y,
        MUTED, side ? "left" : "right", "10px");
    });
  }
  units.slice(0, 2).forEach((unit, side) => {
    label(ctx, unit, side ? right + 6 : left - 6, 6, INK, side ? "left" : "right", "10px");
  });
  for (let t = Math.ceil(t0 / tick) * tick; t <= t1 + 1e-9; t += tick) {
    label(ctx, `${t} s`, X(t), bottom + 12, MUTED, "center", "10px");
  }
  view.scopeNames.forEach((name, index) => {
    const range = ranges.get(unitOf(name));
    ctx.strokeStyle = PALETTE[index % PALETTE.length];
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    let drawing = false;
    for (const sample of samples) {
      const value = sample[index + 1];
      if (value === null) {
        drawing = false;
      } else if (drawing) {
        ctx.lineTo(X(sample[0]), Y(value, range));
      } else {
        ctx.moveTo(X(sample[0]), Y(value, range));
        drawing = true;
      }
    }
    ctx.stroke();
  });
}

function renderLegend() {
  const legend = $("legend");
  const last = view.samples.length ? view.samples[view.samples.length - 1] : [];
  const items = view.scopeNames.map((name, index) => {
    const value = last[index + 1];
    return `<span><span class="swatch" style="background:${PALETTE[index % PALETTE.length]}">`
      + `</span>${escapeHtml(name)} <span class="value">${format(value, 3)} `
      + `${escapeHtml(unitOf(name))}</span></span>`;
  });
  legend.innerHTML = items.join("");
}

function buildPicker() {
  const box = $("signals");
  const all = view.hello ? view.hello.signals : [];
  const filter = $("filter").value.trim();
  const shown = all.filter((name) => name.includes(filter)).slice(0, PICKER_LIMIT);
  box.replaceChildren(...shown.map((name) => {
    const item = document.createElement("label");
    const box = document.createElement("input");
    box.type = "checkbox";
    box.value = name;
    box.checked = view.scopeNames.includes(name);
    box.addEventListener("change", () => choose(name, box.checked));
    item.append(box, ` ${name}`);
    return item;
  }));
}

function choose(name, on) {
  let names = view.scopeNames.filter((other) => other !== name);
  if (on) {
    names = [...names, name].slice(-SCOPE_LIMIT);
  }
  send({op: "scope", signals: names});
}

function escapeHtml(text) {
  return text.replace(/[&<>"]/g, (c) => ({"&": "&amp;", "<": "&lt;", ">": "&gt;", "\"": "&quot;"})[c]);
}

// -- the objects table --------------------------------------------------------------------

// one line per object; an object in error gets a second line under it with the error id and
// message across the table, so that a long message never widens the table
function tableLines(row) {
  const line = document.createElement("tr");
  line.dataset.kind = row.kind;
  line.dataset.name = row.name;
  for (const column of COLUMNS) {
    const cell = document.createElement("td");
    cell.className = column;
    line.appendChild(cell);
  }
  const note = document.createElement("tr");
  note.className = "error-line";
  const cell = document.createElement("td");
  cell.className = "error";
  cell.colSpan = COLUMNS.length;
  note.appendChild(cell);
  return {line, note};
}

function renderTable(frame) {
  const body = $("objects").tBodies[0];
  const seen = new Set();
  const order = [];
  for (const row of frame.rows) {
    const key = `${row.kind}/${row.name}`;
    seen.add(key);
    if (!view.rows.has(key)) {
      view.rows.set(key, tableLines(row));
    }
    const {line, note} = view.rows.get(key);
    COLUMNS.forEach((column, i) => {
      if (line.cells[i].textContent !== row[column]) {
        setBreakable(line.cells[i], row[column]);
      }
    });
    line.classList.toggle("error", row.error !== "");
    order.push(line);
    if (row.error !== "") {
      if (note.cells[0].textContent !== row.error) {
        setBreakable(note.cells[0], row.error);
      }
      order.push(note);
    }
  }
  order.forEach((element, index) => {
    if (body.children[index] !== element) {
      body.insertBefore(element, body.children[index] || null);
    }
  });
  while (body.children.length > order.length) {
    body.lastElementChild.remove();
  }
  for (const key of [...view.rows.keys()]) {
    if (!seen.has(key)) {
      view.rows.delete(key);
    }
  }
  $("hidden-rows").textContent = frame.hidden_rows ? `and ${frame.hidden_rows} more objects` : "";
}

// the text with a chance to break after every "_" (discrete_motion, move_absolute, error ids),
// so that a narrow table wraps it rather than running out of its panel
function setBreakable(cell, text) {
  const nodes = [];
  text.split("_").forEach((part, index, parts) => {
    if (index) {
      nodes.push(document.createElement("wbr"));
    }
    nodes.push(index < parts.length - 1 ? `${part}_` : part);
  });
  cell.replaceChildren(...nodes);
}

bindControls();
connect();
