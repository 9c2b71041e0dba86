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
  // half width and half height of the view, and its centre from the ego, metres
  const [HW, HH, DX, DY] = data.window;

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
  // the road surface under the seen region (drawn translucent over it): a shadow on the carriageway is grey against
  // the region's blue, as clear as one beside the road; its edges above the region
  const roadLayer = el("g", { id: "road" }, world);
  const regionLayer = el("g", { id: "region", "fill-opacity": 0.85 }, world);
  const staticLayer = el("g", { id: "statics" }, world);
  if (data.surfaces.length) {  // one path, its holes by the even-odd rule
    const d = data.surfaces.map((ring) => "M " + pts(ring).split(" ").join(" L ") + " Z").join(" ");
    el("path", { d: d, fill: "#a8a8a8", "fill-rule": "evenodd", stroke: "none" }, roadLayer);
    el("path", { d: d, fill: "none", stroke: "#7a7a7a", "stroke-width": 0.1 }, staticLayer);
  }
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
  const overlay = el("g", { id: "overlay" }, svg);  // in screen units of the view box: the scale bar
  slider.max = data.frames.length - 1;

  // a round length (1, 2 or 5 times a power of ten) of about a fifth of the width, as in the other pictures
  function niceLength(width) {
    const target = width / 5, power = Math.pow(10, Math.floor(Math.log10(target)));
    return [5, 2, 1].map((m) => m * power).find((v) => v <= target);
  }
  // a sensor's field of view as an SVG path (y up in metres, drawn with y flipped), or a circle all around
  function fieldPath(x, y, heading, fov, range) {
    const r = range === null ? 4 * Math.hypot(HW, HH) : range;
    if (fov >= 2 * Math.PI - 1e-9) return null;
    const a0 = heading - fov / 2, a1 = heading + fov / 2;
    const p0 = [x + r * Math.cos(a0), -(y + r * Math.sin(a0))], p1 = [x + r * Math.cos(a1), -(y + r * Math.sin(a1))];
    const large = fov > Math.PI ? 1 : 0;
    return `M ${x} ${-y} L ${p0[0]} ${p0[1]} A ${r} ${r} 0 ${large} 0 ${p1[0]} ${p1[1]} Z`;
  }
  function overlaps(a, b) { return a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]; }
  // a share as a label says it: "<1%" and ">99%" where rounding would say 0% or 100% of a partly hidden one
  function percent(v) { return v > 0 && v < 0.005 ? "<1%" : v < 1 && v >= 0.995 ? ">99%" : `${Math.round(v * 100)}%`; }

  function draw(k) {
    const f = data.frames[k];
    frameLayer.replaceChildren();
    regionLayer.replaceChildren();
    overlay.replaceChildren();
    const [ex, ey] = f.ego;
    const view = [ex + DX - HW, -(ey + DY) - HH, 2 * HW, 2 * HH];
    svg.setAttribute("viewBox", view.join(" "));
    for (const rings of f.region) {  // a polygon: its outline, then its holes (even-odd)
      const d = rings.map((ring) => "M " + pts(ring).split(" ").join(" L ") + " Z").join(" ");
      el("path", { d: d, fill: "#cfe8f7", "fill-rule": "evenodd", stroke: "none" }, regionLayer);
    }
    // metres a screen pixel spans (the picture keeps its aspect): labels of 13 px and markers of 7 px at any size
    const shown = svg.getBoundingClientRect();
    const perPixel = shown.width > 0 && shown.height > 0 ? Math.max(2 * HW / shown.width, 2 * HH / shown.height)
      : Math.max(HW, HH) / 350;
    const size = 13 * perPixel;  // label size in metres
    const minimum = 7 * perPixel;  // a road user drawn smaller than this across is a dot of this size
    const x0 = ex + DX - HW, y0 = ey + DY - HH;  // the view's lower left corner, metres, y up
    const placed = [[x0 + 1.45 * HW, y0, x0 + 2 * HW, y0 + 0.2 * HH]];  // the scale bar's corner stays clear
    const labels = [];
    const boxes = f.objects.map((o) => {  // each object's bounding box, metres, y up: [left, bottom, right, top]
      let top = -Infinity, bottom = Infinity, left = Infinity, right = -Infinity;
      for (let j = 0; j < o.ring.length; j += 2) {
        top = Math.max(top, o.ring[j + 1]); bottom = Math.min(bottom, o.ring[j + 1]);
        left = Math.min(left, o.ring[j]); right = Math.max(right, o.ring[j]);
      }
      const cx = (left + right) / 2, cy = (top + bottom) / 2, half = minimum / 2;
      return [Math.min(left, cx - half), Math.min(bottom, cy - half), Math.max(right, cx + half),
              Math.max(top, cy + half)];
    });
    const order = f.objects.map((o, i) => i).sort((a, b) => {
      const oa = f.objects[a], ob = f.objects[b];
      if (oa.ego !== ob.ego) return oa.ego ? -1 : 1;
      const da = Math.hypot(oa.ring[0] - ex, oa.ring[1] - ey), db = Math.hypot(ob.ring[0] - ex, ob.ring[1] - ey);
      return da - db;
    });
    for (const i of order) {
      const o = f.objects[i];
      const [left, bottom, right, top] = boxes[i];
      const small = Math.max(right - left, top - bottom) <= minimum * 1.0001;
      const p = small
        ? el("circle", { cx: (left + right) / 2, cy: -(top + bottom) / 2, r: minimum / 2, fill: o.fill,
            stroke: "#333", "stroke-width": 0.12, "data-idx": o.idx }, frameLayer)
        : el("polygon", { points: pts(o.ring), fill: o.fill, stroke: o.ego ? "#5a2800" : "#333",
            "stroke-width": 0.12, "data-idx": o.idx }, frameLayer);
      p.classList.add(o.ego ? "ego" : "object");
      const t = el("title", {}, p);
      const hiders = o.occluders.map(String).concat(o.statics.map((k) => `static #${k}`));
      t.textContent = o.ego ? `ego idx ${o.idx}` : o.vis === null ? `idx ${o.idx}: no row in the table` :
        `idx ${o.idx}: visibility ${o.vis.toFixed(3)}; hidden by ${hiders.length ? hiders.join(", ") : "nothing"}`;
      const text = o.ego ? `ego ${o.idx}` : o.vis === null ? `${o.idx}: –` : `${o.idx}: ${percent(o.vis)}`;
      const w = 0.62 * size * text.length, h = 1.1 * size, g = 0.3 * size;
      const cx = (left + right) / 2, cy = (bottom + top) / 2;
      // above, below, right, left of the object; never over another label, nor over another road user but for the
      // ego's label; a label with no such place is left out (the road user keeps its colour)
      const choices = [[cx - w / 2, top + g, cx + w / 2, top + g + h], [cx - w / 2, bottom - g - h, cx + w / 2, bottom - g],
                       [right + g, cy - h / 2, right + g + w, cy + h / 2], [left - g - w, cy - h / 2, left - g, cy + h / 2]];
      const free = choices.filter((c) => c[0] >= x0 && c[2] <= x0 + 2 * HW && c[1] >= y0 && c[3] <= y0 + 2 * HH &&
        !placed.some((q) => overlaps(c, q)));
      const clear = free.filter((c) => !boxes.some((b, j) => j !== i && overlaps(c, b)));
      const box = clear[0] || (o.ego ? free[0] : undefined);
      if (!box) continue;
      placed.push(box);
      labels.push([box, text]);
    }
    for (const [box, text] of labels) {  // after every road user: a label is never under one drawn later
      const tag = el("text", { x: (box[0] + box[2]) / 2, y: -(box[1] + 0.25 * size), "font-size": size,
        "text-anchor": "middle", fill: "#222", stroke: "white", "stroke-width": size / 6, "paint-order": "stroke" },
        frameLayer);
      tag.textContent = text;
    }
    f.sensors.forEach(([x, y, heading], j) => {
      const s = data.sensors[j];
      const d = fieldPath(x, y, heading, s.fov, s.range);
      const style = { fill: "none", stroke: s.colour, "stroke-width": 0.25, "data-sensor": s.name };
      if (d) el("path", { d: d, ...style }, frameLayer);
      else if (s.range !== null) el("circle", { cx: x, cy: -y, r: s.range, ...style }, frameLayer);
      el("circle", { cx: x, cy: -y, r: 0.35, fill: s.colour }, frameLayer);
    });
    const star = el("text", { x: ex, y: -ey + 0.8, "font-size": 2.4, "text-anchor": "middle", fill: "white",
      stroke: "black", "stroke-width": 0.1 }, frameLayer);
    star.textContent = "★";
    // scale bar, lower right
    const length = niceLength(2 * HW);
    const x1 = view[0] + view[2] - 0.04 * view[2], y1 = view[1] + view[3] - 0.05 * view[3];
    el("line", { x1: x1 - length, y1: y1, x2: x1, y2: y1, stroke: "#222", "stroke-width": size / 5 }, overlay)
      .setAttribute("id", "scale-bar");
    const st = el("text", { x: x1 - length / 2, y: y1 - 0.5 * size, "font-size": size, "text-anchor": "middle",
      fill: "#222" }, overlay);
    st.textContent = `${length} m`;
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
