/* trcopt plan preview: draws the plan embedded as JSON (#plan-data, schema trcopt.preview/1).
   Hand-written, no dependencies, no network. Lengths mm, times s, speeds mm/min. */
(function () {
  "use strict";
  var NS = "http://www.w3.org/2000/svg";
  var data = JSON.parse(document.getElementById("plan-data").textContent);
  var timing = data.timing;
  var ROLE = { contour: "#1f5fd6", corner: "#f28c00", approach: "#1a9e3a", retract: "#1a9e3a",
    rapid: "#8c8c8c", positioning: "#8c8c8c" };
  var SEV = { error: "#d62020", warning: "#e07800" };
  var START = "#12a150";
  var R6 = 1 / Math.sqrt(6), R2 = Math.SQRT1_2;
  // rows: screen right, screen up (orthographic; the isometric view looks from +X −Y +Z)
  var VIEWS = {
    xy: { m: [[1, 0, 0], [0, 1, 0]], axes: ["X", "Y"] },
    xz: { m: [[1, 0, 0], [0, 0, 1]], axes: ["X", "Z"] },
    yz: { m: [[0, 1, 0], [0, 0, 1]], axes: ["Y", "Z"] },
    iso: { m: [[R2, R2, 0], [-R6, R6, 2 * R6]], axes: null }
  };
  var MARGIN = { l: 54, r: 14, t: 14, b: 30 };
  var NBINS = 48;
  var VIRIDIS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  var state = { view: "xy", colour: timing ? "speed" : "role", scale: 1, tx: 0, ty: 0, W: 600, H: 400,
    hl: null, cursor: null };

  function el(tag, attrs, parent) {
    var e = document.createElementNS(NS, tag);
    for (var k in attrs) { if (attrs[k] !== null && attrs[k] !== undefined) { e.setAttribute(k, attrs[k]); } }
    if (parent) { parent.appendChild(e); }
    return e;
  }
  function html(tag, text, cls, parent) {
    var e = document.createElement(tag);
    if (text !== null && text !== undefined) { e.textContent = text; }
    if (cls) { e.className = cls; }
    if (parent) { parent.appendChild(e); }
    return e;
  }
  function viridis(x) {
    x = Math.max(0, Math.min(1, x)) * (VIRIDIS.length - 1);
    var i = Math.min(Math.floor(x), VIRIDIS.length - 2), f = x - i, a = VIRIDIS[i], b = VIRIDIS[i + 1];
    return "rgb(" + [0, 1, 2].map(function (k) { return Math.round(a[k] + (b[k] - a[k]) * f); }).join(",") + ")";
  }
  function nice(x) {
    var e = Math.pow(10, Math.floor(Math.log10(x))), f = x / e;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * e;
  }
  function fmt(v, step) {
    var d = Math.max(0, Math.min(6, -Math.floor(Math.log10(step) + 1e-9)));
    var t = v.toFixed(d);
    return t === "-0" || /^-0\.0*$/.test(t) ? t.slice(1) : t;
  }
  function blockName(o) { return o.block ? o.block : "line " + o.line; }

  // ------------------------------------------------------------------ the drawing
  var svg = document.getElementById("view");
  var layers = {};
  layers.grid = el("g", { "class": "grid", id: "layer-grid" }, svg);
  // what moves with the drawing: during a pan or zoom of a large plan only this group's transform changes
  var content = el("g", { id: "content" }, svg);
  ["tools", "prog", "omit", "speed", "tp", "arrows", "start", "marks", "cursor"]
    .forEach(function (name) { layers[name] = el("g", { "class": name, id: "layer-" + name }, content); });
  ["axis", "overlay"].forEach(function (name) { layers[name] = el("g", { "class": name, id: "layer-" + name }, svg); });
  var LARGE = data.toolpath.length + data.programmed.length > 1500;
  var arrowPath = el("path", { "class": "arrows", fill: "#333", stroke: "none" }, layers.arrows);

  var progEls = data.programmed.map(function (s, i) {
    return el("path", { "class": "prog", "data-i": i, "data-line": s.line, "data-block": s.block,
      "stroke-dasharray": s.rapid ? "3 4" : null, "pointer-events": "none" }, layers.prog);
  });
  // the thin programmed line is hovered through a wider invisible twin
  var progHits = data.programmed.map(function (s, i) {
    return el("path", { "class": "prog-hit", "data-i": i, stroke: "#000", "stroke-opacity": 0, "stroke-width": 7,
      fill: "none", "pointer-events": "stroke" }, layers.prog);
  });
  var segEls = data.toolpath.map(function (s, i) {
    return el("path", { "class": "seg", "data-i": i, "data-line": s.line, "data-block": s.block,
      "data-role": s.role, "data-rapid": s.rapid ? "1" : "0", "pointer-events": "stroke" }, layers.tp);
  });
  var toolEls = data.tools.map(function (t) {
    var pts = [];
    for (var k = 0; k <= 40; k++) {
      var a = 2 * Math.PI * k / 40, c = Math.cos(a) * t.r, s = Math.sin(a) * t.r;
      pts.push([0, 1, 2].map(function (j) { return t.c[j] + c * t.u[j] + s * t.v[j]; }));
    }
    return { el: el("path", { "class": "tool" }, layers.tools), pts: pts };
  });
  var omitEls = [];
  var markEls = data.diagnostics.map(function (d, k) {
    if (!d.at) { return null; }
    if (d.kind === "omitted" && d.path === "programmed") {
      omitEls.push({ el: el("path", { "class": "omitted", "data-line": d.line }, layers.omit), seg: d.index });
    }
    var g = el("g", { "class": "mark " + d.severity, id: "mark-" + k, "data-k": k }, layers.marks);
    el("circle", { r: 7, fill: SEV[d.severity] || "#d62020", stroke: SEV[d.severity] || "#d62020" }, g);
    var label = el("text", { fill: SEV[d.severity] || "#d62020" }, g);
    label.textContent = (d.kind === "omitted" ? "omitted " : d.kind === "stop" ? "stopped: " : "") +
      d.severity + " " + (d.alarm !== null ? d.alarm : d.code) + (d.block ? " (" + d.block + ")" : "");
    return g;
  });
  var speedRuns = [];
  if (timing) {
    var vmax = timing.vmax > 0 ? timing.vmax : 1;
    timing.along.forEach(function (pts, i) {
      if (data.toolpath[i].rapid || pts.length < 2) { return; }
      var bin = function (v) { return Math.max(0, Math.min(NBINS - 1, Math.floor(v / vmax * NBINS))); };
      var run = [pts[0]], b = bin(pts[0][3]);
      var flush = function () {
        speedRuns.push({ i: i, pts: run, el: el("path", { stroke: viridis((b + 0.5) / NBINS), "data-i": i }, layers.speed) });
      };
      for (var k = 1; k < pts.length; k++) {
        var bk = bin(pts[k][3]);
        if (bk !== b) {
          if (run.length > 1) { flush(); run = [pts[k - 1]]; }
          b = bk;
        }
        run.push(pts[k]);
      }
      flush();
    });
  }
  var firstPoint = data.toolpath.length ? data.toolpath[0].p[0] : data.programmed.length ? data.programmed[0].p[0] : null;
  var startEl = null;
  if (firstPoint) {
    startEl = el("g", { "class": "start", id: "start" }, layers.start);
    el("path", { d: "M -7 -8 L 9 0 L -7 8 Z", fill: START, stroke: "#fff", "stroke-width": 1 }, startEl);
    el("text", { x: 11, y: -8, fill: START }, startEl).textContent = "start";
  }
  var cursorDot = el("circle", { id: "cursor", r: 6, fill: "#ff2d95", stroke: "#fff", "stroke-width": 2, visibility: "hidden" },
    layers.cursor);

  function project(p) {
    var m = VIEWS[state.view].m;
    return [m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2], m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2]];
  }
  function toPx(p) {
    var q = project(p);
    return [state.tx + state.scale * q[0], state.ty - state.scale * q[1]];
  }
  function pathD(pts) {
    var out = "";
    for (var k = 0; k < pts.length; k++) {
      var q = toPx(pts[k]);
      out += (k ? "L" : "M") + q[0].toFixed(1) + " " + q[1].toFixed(1);
    }
    return out;
  }
  function allPoints() {
    var pts = [];
    data.programmed.forEach(function (s) { Array.prototype.push.apply(pts, s.p); });
    data.toolpath.forEach(function (s) { Array.prototype.push.apply(pts, s.p); });
    toolEls.forEach(function (t) { for (var k = 0; k < t.pts.length; k += 5) { pts.push(t.pts[k]); } });
    return pts;
  }
  function measure() {
    var r = svg.getBoundingClientRect();
    state.W = Math.max(200, r.width);
    state.H = Math.max(150, r.height);
  }
  function fit() {
    measure();
    var pts = allPoints();
    if (!pts.length) { pts = [[0, 0, 0]]; }
    var lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    pts.forEach(function (p) {
      var q = project(p);
      for (var j = 0; j < 2; j++) { lo[j] = Math.min(lo[j], q[j]); hi[j] = Math.max(hi[j], q[j]); }
    });
    var w = hi[0] - lo[0], h = hi[1] - lo[1], size = Math.max(w, h, 1e-3);
    var aw = state.W - MARGIN.l - MARGIN.r, ah = state.H - MARGIN.t - MARGIN.b;
    state.scale = 0.92 * Math.min(aw / Math.max(w, 0.05 * size), ah / Math.max(h, 0.05 * size));
    state.tx = MARGIN.l + aw / 2 - state.scale * (lo[0] + hi[0]) / 2;
    state.ty = MARGIN.t + ah / 2 + state.scale * (lo[1] + hi[1]) / 2;
    state.fitScale = state.scale;
    render();
  }

  function segStyle(e, s) {
    var speed = state.colour === "speed" && timing;
    if (s.rapid) {
      e.setAttribute("stroke", ROLE.rapid); e.setAttribute("stroke-width", 1.4);
      e.setAttribute("stroke-dasharray", "6 4"); e.setAttribute("stroke-opacity", 1);
    } else if (speed) {  // the speed layer shows it; the segment is the (invisible, wider) hover target
      e.setAttribute("stroke", "#000"); e.setAttribute("stroke-width", 9);
      e.removeAttribute("stroke-dasharray"); e.setAttribute("stroke-opacity", 0);
    } else {
      e.setAttribute("stroke", ROLE[s.role] || ROLE.contour); e.setAttribute("stroke-width", 2.2);
      e.removeAttribute("stroke-dasharray"); e.setAttribute("stroke-opacity", 1);
    }
  }
  function arrowsD() {
    var out = "";
    data.toolpath.forEach(function (s) {
      var px = s.p.map(toPx), len = 0, k;
      var cum = [0];
      for (k = 1; k < px.length; k++) { len += Math.hypot(px[k][0] - px[k - 1][0], px[k][1] - px[k - 1][1]); cum.push(len); }
      if (len < 26) { return; }
      for (k = 1; k < px.length && cum[k] < len / 2; k++) { /* find the middle */ }
      var a = px[k - 1], b = px[k], d = Math.hypot(b[0] - a[0], b[1] - a[1]);
      if (d < 1e-9) { return; }
      var f = (len / 2 - cum[k - 1]) / d, ux = (b[0] - a[0]) / d, uy = (b[1] - a[1]) / d;
      var mx = a[0] + f * (b[0] - a[0]) + 4 * ux, my = a[1] + f * (b[1] - a[1]) + 4 * uy;
      var p1 = [mx - 9 * ux + 4.5 * uy, my - 9 * uy - 4.5 * ux], p2 = [mx - 9 * ux - 4.5 * uy, my - 9 * uy + 4.5 * ux];
      out += "M" + mx.toFixed(1) + " " + my.toFixed(1) + "L" + p1[0].toFixed(1) + " " + p1[1].toFixed(1) +
        "L" + p2[0].toFixed(1) + " " + p2[1].toFixed(1) + "Z";
    });
    return out;
  }
  function placeMarks() {
    var placed = [];
    data.diagnostics.forEach(function (d, k) {
      var g = markEls[k];
      if (!g) { return; }
      var q = toPx(d.at), text = g.querySelector("text");
      g.querySelector("circle").setAttribute("cx", q[0]); g.querySelector("circle").setAttribute("cy", q[1]);
      // the label stays inside the drawing: to the left of the mark near the right edge, stacked if close
      var width = text.getComputedTextLength() || text.textContent.length * 6.5;
      var x = q[0] + 10, y = q[1] - 10, anchor = "start";
      if (x + width > state.W - MARGIN.r - 2) { x = q[0] - 10; anchor = "end"; }
      while (placed.some(function (p) { return Math.abs(p[1] - y) < 13 && Math.abs(p[0] - x) < width; })) { y -= 13; }
      y = Math.max(12, Math.min(state.H - 4, y));
      placed.push([x, y]);
      text.setAttribute("x", x); text.setAttribute("y", y); text.setAttribute("text-anchor", anchor);
    });
  }
  function drawAxes() {
    var grid = layers.grid, axis = layers.axis, over = layers.overlay;
    grid.textContent = ""; axis.textContent = ""; over.textContent = "";
    var W = state.W, H = state.H, v = VIEWS[state.view], s = state.scale;
    var step = nice(85 / s);
    if (v.axes) {
      var x0 = (MARGIN.l - state.tx) / s, x1 = (W - MARGIN.r - state.tx) / s;
      var y0 = (state.ty - (H - MARGIN.b)) / s, y1 = (state.ty - MARGIN.t) / s;
      var ticks = [];
      for (var x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
        var px = state.tx + s * x;
        el("line", { x1: px, x2: px, y1: MARGIN.t, y2: H - MARGIN.b, "class": Math.abs(x) < step / 1e6 ? "zero" : "" }, grid);
        ticks.push(["x", px, fmt(x, step)]);
      }
      for (var y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
        var py = state.ty - s * y;
        el("line", { x1: MARGIN.l, x2: W - MARGIN.r, y1: py, y2: py }, grid);
        ticks.push(["y", py, fmt(y, step)]);
      }
      el("rect", { x: 0, y: 0, width: MARGIN.l, height: H, fill: "#fff" }, axis);
      el("rect", { x: 0, y: H - MARGIN.b, width: W, height: MARGIN.b, fill: "#fff" }, axis);
      el("rect", { x: MARGIN.l, y: MARGIN.t, width: W - MARGIN.l - MARGIN.r, height: H - MARGIN.t - MARGIN.b,
        fill: "none", stroke: "#999" }, axis);
      ticks.forEach(function (t) {
        if (t[0] === "x") {
          el("line", { x1: t[1], x2: t[1], y1: H - MARGIN.b, y2: H - MARGIN.b + 4, stroke: "#999" }, axis);
          el("text", { x: t[1], y: H - MARGIN.b + 15, "text-anchor": "middle" }, axis).textContent = t[2];
        } else {
          el("line", { x1: MARGIN.l - 4, x2: MARGIN.l, y1: t[1], y2: t[1], stroke: "#999" }, axis);
          el("text", { x: MARGIN.l - 6, y: t[1] + 3.5, "text-anchor": "end" }, axis).textContent = t[2];
        }
      });
      el("text", { x: W - MARGIN.r, y: H - 4, "text-anchor": "end", "font-weight": "bold", "class": "axis-name" }, axis)
        .textContent = v.axes[0] + " [mm]";
      el("text", { x: 4, y: 11, "font-weight": "bold", "class": "axis-name" }, axis).textContent = v.axes[1] + " [mm]";
    } else {  // isometric: an axis triad instead of a grid
      var o = [MARGIN.l + 10, H - MARGIN.b - 14];
      ["X", "Y", "Z"].forEach(function (name, j) {
        var e = [0, 0, 0]; e[j] = 1;
        var q = project(e), tip = [o[0] + 34 * q[0], o[1] - 34 * q[1]];
        el("line", { x1: o[0], y1: o[1], x2: tip[0], y2: tip[1], stroke: "#555", "stroke-width": 1.5 }, over);
        el("text", { x: tip[0] + 4 * q[0], y: tip[1] - 4 * q[1] + 4, "font-weight": "bold", "class": "axis-name" }, over)
          .textContent = name;
      });
    }
    // scale bar: a length parallel to the screen, in mm
    var bar = step * s, bx = W - MARGIN.r - 12 - bar, by = H - MARGIN.b - 12;
    el("path", { d: "M" + bx + " " + (by - 4) + "v4h" + bar + "v-4", fill: "none", stroke: "#222", "stroke-width": 1.5,
      id: "scale-bar" }, over);
    el("text", { x: bx + bar / 2, y: by - 7, "text-anchor": "middle", id: "scale-label" }, over).textContent = fmt(step, step) + " mm";
  }
  function render() {
    state.pending = false;
    if (state.timer) { window.clearTimeout(state.timer); state.timer = null; }
    content.removeAttribute("transform");
    state.rendered = { scale: state.scale, tx: state.tx, ty: state.ty };
    drawAxes();
    progEls.forEach(function (e, i) {
      var d = pathD(data.programmed[i].p);
      e.setAttribute("d", d); progHits[i].setAttribute("d", d);
    });
    segEls.forEach(function (e, i) { e.setAttribute("d", pathD(data.toolpath[i].p)); segStyle(e, data.toolpath[i]); });
    toolEls.forEach(function (t) { t.el.setAttribute("d", pathD(t.pts)); });
    omitEls.forEach(function (o) { o.el.setAttribute("d", pathD(data.programmed[o.seg].p)); });
    speedRuns.forEach(function (r) { r.el.setAttribute("d", pathD(r.pts)); });
    layers.speed.style.display = state.colour === "speed" && timing ? "" : "none";
    layers.prog.style.display = document.getElementById("show-prog").checked ? "" : "none";
    layers.tools.style.display = document.getElementById("show-tool").checked ? "" : "none";
    layers.arrows.style.display = document.getElementById("show-arrows").checked ? "" : "none";
    arrowPath.setAttribute("d", arrowsD());
    if (startEl) {
      var q = toPx(firstPoint);
      startEl.setAttribute("transform", "translate(" + q[0].toFixed(1) + " " + q[1].toFixed(1) + ")");
    }
    placeMarks();
    placeCursor();
  }
  function placeCursor() {  // in the coordinates of the last full drawing (the content group's)
    if (!state.cursor || !state.rendered) { return; }
    var q = project(state.cursor), r = state.rendered;
    cursorDot.setAttribute("cx", r.tx + r.scale * q[0]); cursorDot.setAttribute("cy", r.ty - r.scale * q[1]);
  }
  function scheduleRender() {
    if (LARGE && state.rendered) {  // move the drawn picture now, redraw it when the motion stops
      var f = state.scale / state.rendered.scale;
      content.setAttribute("transform", "translate(" + (state.tx - f * state.rendered.tx) + " " +
        (state.ty - f * state.rendered.ty) + ") scale(" + f + ")");
      drawAxes();
      if (state.timer) { window.clearTimeout(state.timer); }
      state.timer = window.setTimeout(render, 150);
      return;
    }
    if (!state.pending) { state.pending = true; window.requestAnimationFrame(render); }
  }
  function setView(name) {
    state.view = name;
    document.querySelectorAll("button.view").forEach(function (b) { b.classList.toggle("on", b.dataset.view === name); });
    svg.dataset.view = name;
    fit();
  }
  function setColour(name) {
    if (name === "speed" && !timing) { return; }
    state.colour = name;
    document.querySelectorAll("button.colour").forEach(function (b) { b.classList.toggle("on", b.dataset.colour === name); });
    buildLegend();
    render();
  }

  // ------------------------------------------------------------------ pan, zoom
  svg.addEventListener("wheel", function (ev) {
    ev.preventDefault();
    var r = svg.getBoundingClientRect(), mx = ev.clientX - r.left, my = ev.clientY - r.top;
    var f = Math.exp(-Math.max(-300, Math.min(300, ev.deltaY)) * 0.0018);
    state.scale *= f; state.tx = mx - (mx - state.tx) * f; state.ty = my - (my - state.ty) * f;
    scheduleRender();
  }, { passive: false });
  var drag = null;
  svg.addEventListener("pointerdown", function (ev) {
    if (ev.button !== 0) { return; }
    drag = { x: ev.clientX, y: ev.clientY, tx: state.tx, ty: state.ty, moved: false, id: ev.pointerId };
  });
  svg.addEventListener("pointermove", function (ev) {
    if (!drag) { return; }
    var dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
    if (!drag.moved && Math.hypot(dx, dy) < 3) { return; }
    if (!drag.moved) { drag.moved = true; svg.classList.add("drag"); svg.setPointerCapture(drag.id); hideTip(); }
    state.tx = drag.tx + dx; state.ty = drag.ty + dy;
    scheduleRender();
  });
  function endDrag() { if (drag) { svg.classList.remove("drag"); drag = null; } }
  svg.addEventListener("pointerup", endDrag);
  svg.addEventListener("pointercancel", endDrag);
  svg.addEventListener("dblclick", fit);
  window.addEventListener("resize", function () {
    var cx = (state.W / 2 - state.tx) / state.scale, cy = (state.ty - state.H / 2) / state.scale;
    measure();
    state.tx = state.W / 2 - cx * state.scale; state.ty = state.H / 2 + cy * state.scale;
    render(); drawPlot();
  });

  // ------------------------------------------------------------------ hover
  var tip = document.getElementById("tip");
  function showTip(ev, rows, info) {
    tip.textContent = "";
    rows.forEach(function (r) {
      var div = html("div", null, r[1] || null, tip);
      if (r[2]) { html("b", r[2], null, div); }
      div.appendChild(document.createTextNode(r[0]));
    });
    Object.keys(info).forEach(function (k) { tip.dataset[k] = info[k]; });
    tip.hidden = false;
    var x = ev.clientX + 14, y = ev.clientY + 14;
    var w = tip.offsetWidth, h = tip.offsetHeight;
    if (x + w > window.innerWidth - 4) { x = ev.clientX - w - 10; }
    if (y + h > window.innerHeight - 4) { y = ev.clientY - h - 10; }
    tip.style.left = Math.max(2, x) + "px"; tip.style.top = Math.max(2, y) + "px";
  }
  function hideTip() {
    tip.hidden = true;
    ["kind", "block", "line", "index"].forEach(function (k) { delete tip.dataset[k]; });
  }
  function segRows(s, i, programmed) {
    var rows = [[" · line " + s.line + " · " + (programmed ? "programmed " : "") + s.role, null, blockName(s)]];
    var src = data.lines[String(s.line)];
    if (src) { rows.push([src, "src"]); }
    rows.push([s.rapid || s.feed === null ? "rapid traverse" : "F " + +s.feed.toFixed(3) + " mm/min (programmed feed)"]);
    if (!programmed && timing) {
      var along = timing.along[i], vm = 0;
      along.forEach(function (p) { vm = Math.max(vm, p[3] || 0); });
      rows.push(["planned speed up to " + vm.toFixed(0) + " mm/min, t " + timing.t0[i].toFixed(3) + "–" +
        timing.t1[i].toFixed(3) + " s"]);
    }
    if (!programmed && s.r > 0) { rows.push(["tool radius " + s.r + " mm"]); }
    return rows;
  }
  function highlight(i) {
    if (state.hl !== null && segEls[state.hl]) { segEls[state.hl].classList.remove("hl"); }
    state.hl = i;
    if (i !== null && segEls[i]) { segEls[i].classList.add("hl"); }
    plotHighlight(i);
  }
  svg.addEventListener("pointerover", function (ev) {
    if (drag && drag.moved) { return; }
    var t = ev.target, i;
    if (t.classList.contains("seg")) {
      i = +t.dataset.i;
      highlight(i);
      showTip(ev, segRows(data.toolpath[i], i, false),
        { kind: "toolpath", index: i, block: data.toolpath[i].block || "", line: data.toolpath[i].line });
    } else if (t.classList.contains("prog-hit")) {
      i = +t.dataset.i;
      progEls[i].classList.add("hl");
      showTip(ev, segRows(data.programmed[i], i, true),
        { kind: "programmed", index: i, block: data.programmed[i].block || "", line: data.programmed[i].line });
    } else if (t.closest && t.closest("g.mark")) {
      var d = data.diagnostics[+t.closest("g.mark").dataset.k];
      showTip(ev, [[d.text]], { kind: "diagnostic", block: d.block || "", line: d.line });
    }
  });
  svg.addEventListener("pointerout", function (ev) {
    var t = ev.target;
    if (t.classList.contains("seg")) { highlight(null); }
    if (t.classList.contains("prog-hit")) { progEls[+t.dataset.i].classList.remove("hl"); }
    hideTip();
  });

  // ------------------------------------------------------------------ legend, alarms
  function legendRow(parent, draw, label) {
    var row = html("div", null, "row", parent), s = el("svg", { width: 34, height: 14 }, row);
    draw(s);
    html("span", label, null, row);
    return row;
  }
  function line(s, colour, width, dash) {
    el("line", { x1: 2, y1: 7, x2: 32, y2: 7, stroke: colour, "stroke-width": width, "stroke-dasharray": dash }, s);
  }
  function buildLegend() {
    var box = document.getElementById("legend");
    box.textContent = "";
    legendRow(box, function (s) { line(s, "#000", 1); }, "programmed contour");
    if (state.colour === "speed" && timing) {
      var row = html("div", null, "row", box), w = 150, s = el("svg", { width: w + 40, height: 30, id: "speed-scale" }, row);
      var grad = el("linearGradient", { id: "speed-grad" }, el("defs", {}, s));
      VIRIDIS.forEach(function (_, k) {
        el("stop", { offset: k / (VIRIDIS.length - 1), "stop-color": viridis(k / (VIRIDIS.length - 1)) }, grad);
      });
      el("rect", { x: 2, y: 2, width: w, height: 10, fill: "url(#speed-grad)" }, s);
      el("text", { x: 2, y: 25, "font-size": 10 }, s).textContent = "0";
      el("text", { x: w + 2, y: 25, "font-size": 10, "text-anchor": "end" }, s).textContent = timing.vmax.toFixed(0);
      html("div", "tool-centre path coloured by the planned speed, mm/min (cutting moves; rapids grey)", null, box);
    } else {
      [["contour", "tool-centre path"], ["corner", "corner element"], ["approach", "approach / retract"]]
        .forEach(function (r) { legendRow(box, function (s) { line(s, ROLE[r[0]], 2.2); }, r[1]); });
    }
    legendRow(box, function (s) { line(s, ROLE.rapid, 1.4, "6 4"); }, "rapid / positioning");
    legendRow(box, function (s) { el("circle", { cx: 17, cy: 7, r: 6, fill: "none", stroke: "#1f5fd6", "stroke-opacity": 0.4 }, s); },
      "tool at the junctions");
    legendRow(box, function (s) { el("path", { d: "M11 2 L23 7 L11 12 Z", fill: "#333" }, s); }, "direction of travel");
    legendRow(box, function (s) { el("path", { d: "M10 0 L26 7 L10 14 Z", fill: START }, s); }, "start");
    legendRow(box, function (s) { el("circle", { cx: 17, cy: 7, r: 6, fill: SEV.error, "fill-opacity": 0.55 }, s); }, "alarm (error)");
    legendRow(box, function (s) { el("circle", { cx: 17, cy: 7, r: 6, fill: SEV.warning, "fill-opacity": 0.55 }, s); }, "warning");
    legendRow(box, function (s) { line(s, SEV.error, 4, "6 4"); }, "omitted block (not traversed)");
    html("div", "units: mm; feeds and speeds mm/min", null, box);
  }
  function jumpTo(k) {
    var d = data.diagnostics[k];
    if (!d || !d.at) { return; }
    if (state.scale < state.fitScale) { state.scale = state.fitScale; }
    var q = project(d.at);
    state.tx = state.W / 2 - state.scale * q[0];
    state.ty = state.H / 2 + state.scale * q[1];
    render();
    var g = markEls[k];
    g.classList.remove("flash"); void g.getBoundingClientRect(); g.classList.add("flash");
    document.getElementById("stage").scrollIntoView({ block: "nearest" });
  }
  function buildDiags() {
    var list = document.getElementById("diags");
    if (!data.diagnostics.length) { html("li", "none", "none", list); return; }
    data.diagnostics.forEach(function (d, k) {
      var li = html("li", null, d.severity, list);
      var text = d.severity + " " + (d.alarm !== null ? d.alarm : d.code) + (d.block ? " (" + d.block + ")" : "") +
        (d.line ? ", line " + d.line : "") + ": " + d.message;
      if (d.at) {
        var a = html("a", text, null, li);
        a.href = "#mark-" + k; a.dataset.k = k;
        a.addEventListener("click", function (ev) { ev.preventDefault(); jumpTo(k); });
        if (d.kind === "omitted") { html("span", " — omitted block, not traversed", null, li); }
        if (d.kind === "stop") { html("span", " — the program stops here", null, li); }
      } else {
        html("span", text + " (not located)", null, li);
      }
    });
  }
  layers.marks.addEventListener("click", function (ev) {
    var g = ev.target.closest("g.mark");
    if (g) { var a = document.querySelector('#diags a[data-k="' + g.dataset.k + '"]'); if (a) { a.focus(); } }
  });

  // ------------------------------------------------------------------ speed over time
  var plot = document.getElementById("plot"), plotState = null;
  function drawPlot() {
    plot.textContent = "";
    if (!timing) {
      el("text", { x: 10, y: 20 }, plot).textContent = "no feed profile (timing not computed)";
      return;
    }
    var r = plot.getBoundingClientRect(), W = Math.max(300, r.width), H = Math.max(120, r.height);
    var m = { l: 60, r: 14, t: 22, b: 30 }, T = timing.duration_s || 1;
    // the scale spans the cutting moves (speed and feed limit): a rapid above it is clipped
    var vtop = 1, vall = 1;
    timing.v.forEach(function (v, k) {
      vall = Math.max(vall, v);
      if (!data.toolpath[timing.seg[k]].rapid) { vtop = Math.max(vtop, v, timing.feed[k]); }
    });
    vtop = (vtop > 1 ? vtop : vall) * 1.08;
    var X = function (t) { return m.l + (W - m.l - m.r) * t / T; };
    var Y = function (v) { return H - m.b - (H - m.t - m.b) * Math.min(v, vtop) / vtop; };
    var axes = el("g", { "class": "plot-axis" }, plot);
    var tstep = nice(T / 8), vstep = nice(vtop / 5), t, v;
    for (t = 0; t <= T + 1e-9; t += tstep) {
      el("line", { x1: X(t), x2: X(t), y1: m.t, y2: H - m.b, stroke: "#eee" }, axes);
      el("text", { x: X(t), y: H - m.b + 14, "text-anchor": "middle" }, axes).textContent = fmt(t, tstep);
    }
    for (v = 0; v <= vtop; v += vstep) {
      el("line", { x1: m.l, x2: W - m.r, y1: Y(v), y2: Y(v), stroke: "#eee" }, axes);
      el("text", { x: m.l - 5, y: Y(v) + 3.5, "text-anchor": "end" }, axes).textContent = fmt(v, vstep);
    }
    el("rect", { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: "none", stroke: "#999" }, axes);
    el("text", { x: W - m.r, y: H - 3, "text-anchor": "end", "font-weight": "bold" }, axes).textContent = "t [s]";
    el("text", { x: 4, y: 12, "font-weight": "bold" }, axes).textContent = "v [mm/min]";
    var hl = el("rect", { "class": "plot-hl", y: m.t, height: H - m.t - m.b, visibility: "hidden", id: "plot-hl" }, plot);
    var feed = "", speed = "";
    timing.t.forEach(function (tt, k) {
      speed += (k ? "L" : "M") + X(tt).toFixed(1) + " " + Y(timing.v[k]).toFixed(1);
      feed += (k ? "L" + X(tt).toFixed(1) + " " + Y(timing.feed[k - 1]).toFixed(1) + "L" : "M") +
        X(tt).toFixed(1) + " " + Y(timing.feed[k]).toFixed(1);
    });
    var clip = el("clipPath", { id: "plot-clip" }, el("defs", {}, plot));
    el("rect", { x: m.l, y: m.t - 1, width: W - m.l - m.r, height: H - m.t - m.b + 2 }, clip);
    el("path", { d: feed, fill: "none", stroke: "#999", "stroke-dasharray": "4 3", id: "plot-feed", "clip-path": "url(#plot-clip)" }, plot);
    el("path", { d: speed, fill: "none", stroke: "#1f5fd6", "stroke-width": 1.5, id: "plot-speed", "clip-path": "url(#plot-clip)" }, plot);
    el("text", { x: W - m.r, y: 12, "text-anchor": "end", fill: "#666" }, axes).textContent =
      "— path speed   - - feed limit" + (vall > vtop ? "   (rapids up to " + vall.toFixed(0) + " mm/min clipped)" : "");
    var vline = el("line", { y1: m.t, y2: H - m.b, stroke: "#ff2d95", visibility: "hidden", id: "plot-cursor" }, plot);
    var dot = el("circle", { r: 4, fill: "#ff2d95", visibility: "hidden" }, plot);
    var hit = el("rect", { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: "transparent", id: "plot-hit" }, plot);
    plotState = { X: X, hl: hl };
    hit.addEventListener("pointermove", function (ev) {
      var rr = plot.getBoundingClientRect(), tq = (ev.clientX - rr.left - m.l) / (W - m.l - m.r) * T;
      var lo = 0, hi = timing.t.length - 1;
      while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (timing.t[mid] <= tq) { lo = mid; } else { hi = mid; } }
      var k = Math.abs(timing.t[hi] - tq) < Math.abs(timing.t[lo] - tq) ? hi : lo, i = timing.seg[k];
      vline.setAttribute("x1", X(timing.t[k])); vline.setAttribute("x2", X(timing.t[k]));
      dot.setAttribute("cx", X(timing.t[k])); dot.setAttribute("cy", Y(timing.v[k]));
      vline.setAttribute("visibility", "visible"); dot.setAttribute("visibility", "visible");
      state.cursor = timing.xyz[k];
      cursorDot.setAttribute("visibility", "visible");
      highlight(i);
      placeCursor();
      var s = data.toolpath[i];
      showTip(ev, [[" · line " + s.line + " · " + s.role, null, blockName(s)],
        ["t " + timing.t[k].toFixed(3) + " s, speed " + timing.v[k].toFixed(0) + " mm/min"]],
        { kind: "plot", index: i, block: s.block || "", line: s.line });
    });
    hit.addEventListener("pointerleave", function () {
      vline.setAttribute("visibility", "hidden"); dot.setAttribute("visibility", "hidden");
      cursorDot.setAttribute("visibility", "hidden"); state.cursor = null;
      highlight(null); hideTip();
    });
  }
  function plotHighlight(i) {
    if (!plotState || !timing) { return; }
    if (i === null || i === undefined) { plotState.hl.setAttribute("visibility", "hidden"); return; }
    var x0 = plotState.X(timing.t0[i]), x1 = plotState.X(timing.t1[i]);
    plotState.hl.setAttribute("x", x0); plotState.hl.setAttribute("width", Math.max(1, x1 - x0));
    plotState.hl.setAttribute("visibility", "visible");
  }

  // ------------------------------------------------------------------ start
  document.getElementById("summary").textContent = data.summary;
  document.querySelectorAll("button.view").forEach(function (b) {
    b.addEventListener("click", function () { setView(b.dataset.view); });
  });
  document.querySelectorAll("button.colour").forEach(function (b) {
    if (b.dataset.colour === "speed" && !timing) { b.disabled = true; b.title = "no feed profile (timing not computed)"; }
    b.addEventListener("click", function () { setColour(b.dataset.colour); });
  });
  ["show-prog", "show-tool", "show-arrows"].forEach(function (id) { document.getElementById(id).addEventListener("change", render); });
  document.getElementById("fit").addEventListener("click", fit);
  if (!timing) { document.getElementById("plot-box").hidden = true; }
  buildDiags();
  setColour(state.colour);
  setView("xy");
  drawPlot();
  window.trcoptPreview = { data: data, state: state, setView: setView, setColour: setColour, fit: fit, jumpTo: jumpTo };
  document.body.dataset.ready = "1";
})();
