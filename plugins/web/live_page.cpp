#include "plugins/web/live_page.hpp"

namespace luxloc {

std::string_view live_page_html() {
  static constexpr std::string_view kPage = R"PAGE(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>luxloc live</title>
<meta name="viewport" content="width=device-width,initial-scale=1">
<style>
body{font:14px system-ui,sans-serif;margin:0;background:#111;color:#ddd;display:flex;flex-wrap:wrap}
#map{background:#1b1b1b;flex:1 1 640px;min-width:320px;height:calc(100vh - 16px);margin:8px}
#side{flex:0 0 300px;padding:8px}
h1{font-size:16px;margin:4px 0 8px}
table{border-collapse:collapse;width:100%}td{padding:2px 4px;border-bottom:1px solid #333}
td:last-child{text-align:right;font-variant-numeric:tabular-nums}
.dim{color:#888}#conn.live{color:#6c6}#conn.down{color:#e66}
</style></head><body>
<canvas id="map" data-draws="0"></canvas>
<div id="side">
<h1>luxloc <span id="device" class="dim"></span> <span id="conn">connecting</span></h1>
<table>
<tr><td>t</td><td><span id="pose-t">-</span> s</td></tr>
<tr><td>x, y</td><td><span id="pose-x">-</span>, <span id="pose-y">-</span> m</td></tr>
<tr><td>yaw</td><td><span id="pose-yaw">-</span> deg</td></tr>
<tr><td>sigma x, y</td><td><span id="sigma">-</span> m</td></tr>
<tr><td>mode</td><td id="mode">-</td></tr>
<tr><td>motion</td><td id="motion">-</td></tr>
<tr><td>LEDs in view</td><td id="leds-in-view">-</td></tr>
<tr><td>latency p50 / p99</td><td><span id="latency">-</span> ms</td></tr>
<tr><td>poses received</td><td id="pose-count">0</td></tr>
<tr><td>time covered</td><td><span id="t-span">0</span> s</td></tr>
<tr><td>trajectory points</td><td id="trail-points">0</td></tr>
<tr><td>LEDs on the map</td><td id="map-leds">0</td></tr>
<tr><td>particles drawn</td><td id="cloud-points">0</td></tr>
</table>
<h1>sources</h1>
<table><thead><tr><td class="dim">source</td><td class="dim">rate /s</td><td class="dim">drops</td></tr></thead>
<tbody id="sources"></tbody></table>
<h1 id="camera-title" hidden>camera</h1>
<img id="camera" alt="camera frame, identified LEDs circled" hidden style="width:100%;image-rendering:auto">
<p class="dim">Read-only view. The ellipse holds the position with 95 % probability (2.45 sigma).</p>
</div>
<script>
"use strict";
const $ = id => document.getElementById(id);
const token = new URLSearchParams(location.search).get("token");
let leds = [], trail = [], pose = null, count = 0, firstT = null, cloud = [];
const canvas = $("map"), ctx = canvas.getContext("2d");
function bounds() {
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  const add = (x, y) => { x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y); };
  leds.forEach(l => add(l.x, l.y));
  trail.forEach(p => add(p[1], p[2]));
  if (pose) add(pose.x, pose.y);
  if (!isFinite(x0)) { x0 = 0; y0 = 0; x1 = 1; y1 = 1; }
  return [x0 - 0.7, y0 - 0.7, x1 + 0.7, y1 + 0.7];
}
function draw() {
  const w = canvas.clientWidth || 640, h = canvas.clientHeight || 480;
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  const [x0, y0, x1, y1] = bounds();
  const s = Math.min(w / (x1 - x0), h / (y1 - y0));
  const X = x => (x - x0) * s, Y = y => h - (y - y0) * s;  // world y up
  ctx.clearRect(0, 0, w, h);
  ctx.strokeStyle = "#2a2a2a"; ctx.lineWidth = 1;  // 1 m grid
  for (let gx = Math.ceil(x0); gx <= x1; gx++) { ctx.beginPath(); ctx.moveTo(X(gx), 0); ctx.lineTo(X(gx), h); ctx.stroke(); }
  for (let gy = Math.ceil(y0); gy <= y1; gy++) { ctx.beginPath(); ctx.moveTo(0, Y(gy)); ctx.lineTo(w, Y(gy)); ctx.stroke(); }
  ctx.font = "11px sans-serif";
  for (const l of leds) {
    ctx.fillStyle = "#fc3"; ctx.beginPath(); ctx.arc(X(l.x), Y(l.y), 6, 0, 2 * Math.PI); ctx.fill();
    ctx.fillStyle = "#aaa"; ctx.fillText(l.id + " (" + Math.round(l.f) + " Hz)", X(l.x) + 8, Y(l.y) - 6);
  }
  ctx.fillStyle = "rgba(255,120,120,0.45)";  // particles, subsampled
  for (const q of cloud) ctx.fillRect(X(q[0]) - 1, Y(q[1]) - 1, 2, 2);
  if (trail.length > 1) {
    ctx.strokeStyle = "#39f"; ctx.lineWidth = 2; ctx.beginPath();
    trail.forEach((p, i) => i ? ctx.lineTo(X(p[1]), Y(p[2])) : ctx.moveTo(X(p[1]), Y(p[2])));
    ctx.stroke();
  }
  if (pose) {
    const cx = X(pose.x), cy = Y(pose.y);
    if (pose.sx !== undefined && pose.sy !== undefined) {
      ctx.strokeStyle = "#f66"; ctx.lineWidth = 1.5; ctx.beginPath();
      ctx.ellipse(cx, cy, Math.max(2, 2.45 * pose.sx * s), Math.max(2, 2.45 * pose.sy * s), 0, 0, 2 * Math.PI); ctx.stroke();
    }
    ctx.fillStyle = "#fff"; ctx.beginPath(); ctx.arc(cx, cy, 4, 0, 2 * Math.PI); ctx.fill();
    ctx.strokeStyle = "#fff"; ctx.beginPath(); ctx.moveTo(cx, cy);
    ctx.lineTo(cx + 18 * Math.cos(pose.yaw), cy - 18 * Math.sin(pose.yaw)); ctx.stroke();
  }
  canvas.dataset.draws = String(Number(canvas.dataset.draws) + 1);
}
const fixed = (v, n) => v === undefined ? "-" : v.toFixed(n);
const es = new EventSource("events" + (token ? "?token=" + encodeURIComponent(token) : ""));
es.onopen = () => { $("conn").textContent = "live"; $("conn").className = "live"; };
es.onerror = () => { $("conn").textContent = "reconnecting"; $("conn").className = "down"; };
es.addEventListener("init", e => {
  const d = JSON.parse(e.data);
  leds = d.leds; trail = d.trail;
  $("device").textContent = d.device; $("map-leds").textContent = leds.length;
  $("trail-points").textContent = trail.length;
  draw();
});
es.addEventListener("pose", e => {
  const p = JSON.parse(e.data);
  pose = p; count++;
  if (firstT === null) firstT = p.t;
  trail.push([p.t, p.x, p.y]);
  if (trail.length > 20000) trail.splice(0, trail.length - 20000);
  $("pose-t").textContent = fixed(p.t, 2); $("pose-x").textContent = fixed(p.x, 2); $("pose-y").textContent = fixed(p.y, 2);
  $("pose-yaw").textContent = fixed(p.yaw * 180 / Math.PI, 1);
  $("sigma").textContent = fixed(p.sx, 3) + ", " + fixed(p.sy, 3);
  $("mode").textContent = p.mode || "-"; $("motion").textContent = p.motion || "-";
  $("leds-in-view").textContent = p.leds;
  $("pose-count").textContent = count; $("t-span").textContent = (p.t - firstT).toFixed(2);
  $("trail-points").textContent = trail.length;
  draw();
});
es.addEventListener("status", e => {
  const d = JSON.parse(e.data);
  if (d.latency_p50_ms !== undefined) $("latency").textContent = fixed(d.latency_p50_ms, 2) + " / " + fixed(d.latency_p99_ms, 2);
  const rows = Object.keys(d.rates_hz).map(n => "<tr><td></td><td>" + d.rates_hz[n].toFixed(0) + "</td><td>" +
                                              (d.source_drops[n] || 0) + "</td></tr>");
  $("sources").innerHTML = rows.join("");
  Object.keys(d.rates_hz).forEach((n, i) => { $("sources").rows[i].cells[0].textContent = n; });  // names as text
});
es.addEventListener("cloud", e => {
  cloud = JSON.parse(e.data).p;
  $("cloud-points").textContent = cloud.length;
});
es.addEventListener("frame", e => {
  const d = JSON.parse(e.data), img = $("camera");
  img.hidden = false; $("camera-title").hidden = false;
  img.src = "frame.jpg?n=" + d.n + (token ? "&token=" + encodeURIComponent(token) : "");
  img.dataset.frames = String(d.n);
});
window.addEventListener("resize", draw);
</script></body></html>
)PAGE";
  return kPage;
}

}  // namespace luxloc
