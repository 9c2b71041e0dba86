// Draws the scene of the chosen frame as SVG; the data comes from the JSON script elements of this page.
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("scene-data").textContent);
  const timeline = JSON.parse(document.getElementById("timeline-data").textContent);
  const NS = "http://www.w3.org/2000/svg";
  const svg = document.getElementById("scene");
  const slider = document.getElementById("slider");
  const label = document.getElementById("frame-label");
  const play = document.getElementById("play");
  const R = data.range;
  const H = R * 0.35;

  function el(name, attrs, parent) {
    const e = document.createElementNS(NS, name);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(e);
    return e;
  }
  // flat [x0, y0, x1, y1, ...] in metres -> SVG points, y up
  function pts(flat) {
    const out = [];
    for (let i = 0; i < flat.length; i += 2) out.push(flat[i] + "," + -flat[i + 1]);
    return out.join(" ");
  }

  const defs = el("defs", {}, svg);
  const hatch = el("pattern", { id: "hatch", width: 1.2, height: 1.2, patternUnits: "userSpaceOnUse",
    patternTransform: "rotate(45)" }, defs);
  el("rect", { width: 1.2, height: 1.2, fill: "#e4e4e4" }, hatch);
  el("line", { x1: 0, y1: 0, x2: 0, y2: 1.2, stroke: "#777", "stroke-width": 0.5 }, hatch);
  const world = el("g", { id: "world" }, svg);
  const staticLayer = el("g", { id: "statics" }, world);
  for (const lane of data.lanes) {
    el("polyline", { points: pts(lane), fill: "none", stroke: "#9a9a9a", "stroke-width": 0.15,
      "stroke-dasharray": "1.5 1.5" }, staticLayer);
  }
  for (const s of data.statics) {
    if (s.kind === "polygon") {
      el("polygon", { points: pts(s.points), fill: "url(#hatch)", stroke: "#555", "stroke-width": 0.15 }, staticLayer);
    } else {
      el("polyline", { points: pts(s.points), fill: "none", stroke: "#555", "stroke-width": 0.6 }, staticLayer);
    }
  }
  if (!data.statics.length) document.getElementById("static-key").hidden = true;
  const frameLayer = el("g", { id: "frame" }, world);
  slider.max = data.frames.length - 1;

  function draw(k) {
    const f = data.frames[k];
    frameLayer.replaceChildren();
    const [ex, ey] = f.ego;
    svg.setAttribute("viewBox", `${ex - R} ${-ey - H} ${2 * R} ${2 * H}`);
    for (const ring of f.region) {
      el("polygon", { points: pts(ring), fill: "#ffe680", "fill-opacity": 0.4, stroke: "none" }, frameLayer);
    }
    for (const o of f.objects) {
      const p = el("polygon", { points: pts(o.ring), fill: o.fill, stroke: o.ego ? "#0b2f66" : "#333",
        "stroke-width": 0.12, "data-idx": o.idx }, frameLayer);
      p.classList.add(o.ego ? "ego" : "object");
      const t = el("title", {}, p);
      t.textContent = o.ego ? `ego idx ${o.idx}` :
        `idx ${o.idx}: visibility ${o.vis.toFixed(3)}; hidden by ${o.occluders.length ? o.occluders.join(", ") : "nothing"}`;
      let top = -Infinity, sx = 0;
      for (let i = 0; i < o.ring.length; i += 2) { top = Math.max(top, o.ring[i + 1]); sx += o.ring[i]; }
      const text = el("text", { x: sx / (o.ring.length / 2), y: -top - 0.6, "font-size": 2.2, "text-anchor": "middle",
        fill: "#222" }, frameLayer);
      text.textContent = o.ego ? `ego ${o.idx}` : `${o.idx}: ${Math.round(o.vis * 100)}%`;
    }
    const star = el("text", { x: ex, y: -ey + 0.8, "font-size": 2.4, "text-anchor": "middle", fill: "white",
      stroke: "black", "stroke-width": 0.1 }, frameLayer);
    star.textContent = "★";
    const speed = Number.isFinite(f.speed) ? `${f.speed.toFixed(1)} m/s` : "unknown";
    label.textContent = `frame ${f.frame}, t = ${f.t.toFixed(2)} s, ego speed ${speed}`;
    svg.dataset.frame = f.frame;
    if (timelineView) timelineView.signal("now", f.t).runAsync();
  }

  slider.addEventListener("input", () => draw(Number(slider.value)));
  let timer = null;
  play.addEventListener("click", () => {
    if (timer) { clearInterval(timer); timer = null; play.textContent = "play"; return; }
    play.textContent = "pause";
    timer = setInterval(() => {
      slider.value = (Number(slider.value) + 1) % data.frames.length;
      draw(Number(slider.value));
    }, 100);
  });
  let timelineView = null;  // the timeline's Vega view: its rule follows the slider
  draw(0);
  vegaEmbed("#timeline", timeline.spec, { mode: timeline.mode, actions: false, renderer: "svg" })
    .then((result) => {
      timelineView = result.view;
      draw(Number(slider.value));
      document.body.dataset.timeline = "ready";
    })
    .catch((err) => { console.error("timeline: " + err); });
})();
