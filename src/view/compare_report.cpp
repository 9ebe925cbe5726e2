// The worst pixels and the HTML page of `surftrace compare` (compare_report.hpp).
#include "view/compare_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

#include <nlohmann/json.hpp>

namespace surftrace::view {
namespace {

// As compareFrames decides it: the test's patch kind when it carries kinds, else a finite depth.
bool testHits(const FrameBuffers& test, std::size_t p, const TestChannels& carried) {
  return carried.kind ? test.kind[p] != 0 : std::isfinite(test.depth[p]);
}

// The JSON value of a number that may be NaN or infinite (JSON has neither): null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string base64(const EncodedImage& bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b = static_cast<std::uint32_t>(bytes[i]) << 16 |
                            (i + 1 < bytes.size() ? static_cast<std::uint32_t>(bytes[i + 1]) << 8 : 0u) |
                            (i + 2 < bytes.size() ? static_cast<std::uint32_t>(bytes[i + 2]) : 0u);
    out += kDigits[(b >> 18) & 63];
    out += kDigits[(b >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(b >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[b & 63] : '=';
  }
  return out;
}

std::string escapeHtml(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// JSON inside <script>: "</" would end the element early; "<\/" is the same JSON string.
std::string scriptSafe(const std::string& json) {
  std::string out;
  for (std::size_t i = 0; i < json.size(); ++i) {
    out += json[i];
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') out += '\\';
  }
  return out;
}

// The page's style and script, which build the tables and plots from the embedded report.
constexpr const char* kStyle = R"(
body { font: 14px/1.4 system-ui, sans-serif; margin: 16px; color: #222; background: #fff; }
h1 { font-size: 18px; margin: 0 0 8px; } h2 { font-size: 15px; margin: 18px 0 6px; }
pre { background: #f4f4f4; padding: 8px; overflow-x: auto; font-size: 12px; }
.images { display: flex; gap: 12px; flex-wrap: wrap; }
.panel figcaption { font-weight: 600; margin-bottom: 4px; }
.viewport { width: 360px; height: 360px; overflow: hidden; position: relative; background: #777;
            border: 1px solid #999; cursor: grab; touch-action: none; }
.viewport img { position: absolute; left: 0; top: 0; transform-origin: 0 0; image-rendering: pixelated;
                user-select: none; -webkit-user-drag: none; }
table { border-collapse: collapse; font-size: 13px; }
td, th { border: 1px solid #ccc; padding: 2px 8px; text-align: right; }
th { background: #eee; } td:first-child, th:first-child { text-align: left; }
.plots { display: flex; gap: 12px; flex-wrap: wrap; }
.plots figure, .images figure { margin: 0; }
#pixel { font-family: monospace; min-height: 1.4em; }
)";

constexpr const char* kScript = R"(
const report = JSON.parse(document.getElementById('report').textContent);
const fmt = v => v === null || v === undefined ? '—' : (Number.isInteger(v) ? String(v) : Number(v).toPrecision(4));
function cell(row, value, key) {
  const td = row.insertCell();
  td.textContent = fmt(value);
  if (key) { td.dataset.key = key; td.dataset.value = value === null ? '' : String(value); }
  return td;
}
// The per-kind table.
const kinds = document.getElementById('kinds');
for (const k of report.per_kind) {
  const row = kinds.tBodies[0].insertRow();
  row.insertCell().textContent = k.kind;
  for (const key of ['pixels', 'samples', 'median', 'p1', 'p99']) cell(row, k[key], k.kind + '.' + key);
}
// One histogram of the signed depth error per kind, inline SVG.
const svgNS = 'http://www.w3.org/2000/svg';
const plots = document.getElementById('plots');
for (const k of report.per_kind) {
  const fig = document.createElement('figure');
  const W = 320, H = 150, left = 36, bottom = 22, top = 16;
  const svg = document.createElementNS(svgNS, 'svg');
  svg.setAttribute('width', W); svg.setAttribute('height', H); svg.dataset.panel = 'plot ' + k.kind;
  const counts = k.histogram.counts, most = Math.max(1, ...counts), bw = (W - left - 4) / counts.length;
  const add = (tag, attrs, text) => { const e = document.createElementNS(svgNS, tag);
    for (const a in attrs) e.setAttribute(a, attrs[a]); if (text) e.textContent = text; svg.appendChild(e); return e; };
  add('rect', {x: 0, y: 0, width: W, height: H, fill: '#fafafa'});
  counts.forEach((c, i) => { const h = (H - bottom - top) * c / most;
    add('rect', {x: left + i * bw, y: H - bottom - h, width: Math.max(1, bw - 1), height: h, fill: '#3465a4'}); });
  add('line', {x1: left + (W - left - 4) / 2, x2: left + (W - left - 4) / 2, y1: top, y2: H - bottom, stroke: '#c00'});
  add('text', {x: left, y: H - 6, 'font-size': 10}, fmt(-k.histogram.range));
  add('text', {x: W - 40, y: H - 6, 'font-size': 10}, fmt(k.histogram.range));
  add('text', {x: left + (W - left) / 2 - 4, y: H - 6, 'font-size': 10}, '0 Å');
  add('text', {x: 2, y: top + 8, 'font-size': 10}, String(most));
  add('text', {x: left, y: 11, 'font-size': 11}, k.kind + ': ' + k.samples + ' px, median ' + fmt(k.median) + ' Å');
  fig.appendChild(svg);
  plots.appendChild(fig);
}
// The worst pixels.
const worst = document.getElementById('worst');
for (const w of report.worst_pixels) {
  const row = worst.tBodies[0].insertRow();
  for (const v of [w.x, w.y, w.what, w.kind, w.test_kind]) row.insertCell().textContent = v;
  cell(row, w.depth_error);
  for (const v of w.point) cell(row, v);
  row.insertCell().textContent = w.atom === null ? '—' : String(w.atom);
}
// Zoom (wheel, about the pointer) and pan (drag), the same for every image; double-click resets.
const views = [...document.querySelectorAll('.viewport')], imgs = views.map(v => v.querySelector('img'));
const size = 360;
let scale = size / Math.max(+imgs[0].getAttribute('width'), +imgs[0].getAttribute('height')), tx = 0, ty = 0;
const fit = scale;
function apply() { for (const im of imgs) im.style.transform = `translate(${tx}px, ${ty}px) scale(${scale})`; }
for (const v of views) {
  v.addEventListener('wheel', e => { e.preventDefault(); const r = v.getBoundingClientRect();
    const px = e.clientX - r.left, py = e.clientY - r.top, f = e.deltaY < 0 ? 1.25 : 0.8;
    tx = px - (px - tx) * f; ty = py - (py - ty) * f; scale *= f; apply(); }, {passive: false});
  let drag = null;
  v.addEventListener('pointerdown', e => { drag = [e.clientX - tx, e.clientY - ty]; v.setPointerCapture(e.pointerId); });
  v.addEventListener('pointermove', e => {
    const r = v.getBoundingClientRect(), x = Math.floor((e.clientX - r.left - tx) / scale), y = Math.floor((e.clientY - r.top - ty) / scale);
    document.getElementById('pixel').textContent = 'pixel (' + x + ', ' + y + ')';
    if (drag) { tx = e.clientX - drag[0]; ty = e.clientY - drag[1]; apply(); } });
  v.addEventListener('pointerup', () => { drag = null; });
  v.addEventListener('dblclick', () => { scale = fit; tx = ty = 0; apply(); });
}
apply();
// Where each image and plot was drawn, for a check of the rendered page.
for (const e of document.querySelectorAll('[data-panel]')) {
  const r = e.getBoundingClientRect();
  e.dataset.rect = [r.left, r.top, r.width, r.height].map(Math.round).join(',');
}
document.body.dataset.ready = 'yes';
)";

}  // namespace

std::vector<WorstPixel> worstPixels(const FrameBuffers& test, const FrameBuffers& ref, const ReferenceMasks& masks,
                                    const TestChannels& carried, const Camera* camera, std::size_t count) {
  std::vector<std::tuple<int, double, std::size_t>> ranked;  // class (0 coverage, 1 kind, 2 depth), −|error|, pixel
  for (std::size_t p = 0; p < ref.pixels(); ++p) {
    const PixelMask& m = masks.mask[p];
    if (m.band) continue;
    const bool refHit = ref.kind[p] != 0, testHit = testHits(test, p, carried);
    if (refHit != testHit) ranked.emplace_back(0, 0.0, p);
    else if (!refHit) continue;
    else {
      // NaN (a mismatch, compareFrames) ranks first among the depths, and keeps the sort's order strict.
      const double e = std::abs(static_cast<double>(test.depth[p]) - static_cast<double>(ref.depth[p]));
      ranked.emplace_back(carried.kind && !m.kindSeam && test.kind[p] != ref.kind[p] ? 1 : 2,
                          std::isnan(e) ? -std::numeric_limits<double>::infinity() : -e, p);
    }
  }
  const std::size_t n = std::min(count, ranked.size());
  std::partial_sort(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(n), ranked.end());
  std::vector<WorstPixel> out;
  const std::optional<Camera::Frame> frame = camera ? std::optional(camera->frame()) : std::nullopt;
  for (std::size_t i = 0; i < n; ++i) {
    const auto [what, negError, p] = ranked[i];
    WorstPixel w;
    w.x = static_cast<int>(p % static_cast<std::size_t>(ref.width));
    w.y = static_cast<int>(p / static_cast<std::size_t>(ref.width));
    w.what = what == 0 ? "coverage" : what == 1 ? "kind" : "depth";
    const bool refHit = ref.kind[p] != 0;
    w.depthError = what == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(test.depth[p]) - ref.depth[p];
    w.kind = static_cast<PatchKind>(ref.kind[p]);
    w.testKind = carried.kind ? static_cast<PatchKind>(test.kind[p]) : PatchKind::None;
    const double t = refHit ? ref.depth[p] : test.depth[p];
    w.atom = refHit ? ref.atomId[p] : (carried.kind ? test.atomId[p] : ~0u);
    if (frame) {
      const Ray ray = frame->ray(w.x + 0.5, w.y + 0.5);
      w.point = ray.org + t * ray.dir;
    } else {
      w.point = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
    }
    out.push_back(w);
  }
  return out;
}

nlohmann::json worstPixelsJson(const std::vector<WorstPixel>& pixels) {
  nlohmann::json j = nlohmann::json::array();
  for (const WorstPixel& w : pixels)
    j.push_back({{"x", w.x},
                 {"y", w.y},
                 {"what", w.what},
                 {"depth_error", number(w.depthError)},
                 {"point", {number(w.point.x), number(w.point.y), number(w.point.z)}},
                 {"atom", w.atom == ~0u ? nlohmann::json(nullptr) : nlohmann::json(w.atom)},
                 {"kind", patchKindName(w.kind)},
                 {"test_kind", patchKindName(w.testKind)}});
  return j;
}

std::string comparisonHtml(const HtmlReport& r) {
  const std::string size = "\" width=\"" + std::to_string(r.width) + "\" height=\"" + std::to_string(r.height) + "\"";
  auto image = [&](const char* caption, const EncodedImage& png) {
    return std::string("<figure class=\"panel\"><figcaption>") + caption +
           "</figcaption><div class=\"viewport\" data-panel=\"" + caption + "\"><img alt=\"" + caption + size +
           " src=\"data:image/png;base64," + base64(png) + "\"></div></figure>\n";
  };
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escapeHtml(r.title) +
                     "</title>\n<style>" + kStyle + "</style></head>\n<body>\n<h1>" + escapeHtml(r.title) + "</h1>\n<pre>" +
                     escapeHtml(r.verdict) + "</pre>\n";
  html += "<h2>Images</h2><p>Wheel to zoom, drag to pan (all three together), double-click to fit. <span id=\"pixel\"></span></p>\n";
  html += "<div class=\"images\">\n" + image("test", r.test) + image("reference", r.reference) + image("difference", r.diff) +
          "</div>\n<p><b>Difference:</b> " + escapeHtml(r.legend) + "</p>\n";
  html += "<h2>Signed depth error per patch kind (test − reference, Å)</h2>\n"
          "<table id=\"kinds\"><thead><tr><th>kind</th><th>pixels</th><th>depth samples</th><th>median</th>"
          "<th>p1</th><th>p99</th></tr></thead><tbody></tbody></table>\n<div class=\"plots\" id=\"plots\"></div>\n";
  html += "<h2>Worst pixels</h2>\n<table id=\"worst\"><thead><tr><th>x</th><th>y</th><th>what</th><th>kind</th>"
          "<th>test kind</th><th>depth error (Å)</th><th>hit x</th><th>hit y</th><th>hit z</th><th>atom</th></tr></thead>"
          "<tbody></tbody></table>\n";
  html += "<script type=\"application/json\" id=\"report\">" + scriptSafe(r.reportJson) + "</script>\n<script>" + kScript +
          "</script>\n</body></html>\n";
  return html;
}

EncodedImage displayPng(const FrameBuffers& f, bool hasColor) {
  FrameBuffers image;
  image.width = f.width;
  image.height = f.height;
  if (hasColor && f.rgba.size() == 4 * f.pixels()) {
    image.rgba = f.rgba;
  } else {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const float t : f.depth)
      if (std::isfinite(t)) lo = std::min(lo, static_cast<double>(t)), hi = std::max(hi, static_cast<double>(t));
    image.rgba.assign(4 * f.pixels(), 0.0f);
    for (std::size_t p = 0; p < f.pixels(); ++p) {
      if (!std::isfinite(f.depth[p])) continue;
      const float g = hi > lo ? static_cast<float>(0.9 - 0.7 * (f.depth[p] - lo) / (hi - lo)) : 0.8f;
      for (int k = 0; k < 3; ++k) image.rgba[4 * p + k] = g;
    }
  }
  return encodePng("image.png", image, {});
}

EncodedImage rgbPng(const std::vector<float>& rgb, int width, int height) {
  FrameBuffers image;
  image.width = width;
  image.height = height;
  image.rgba.resize(4 * image.pixels());
  for (std::size_t p = 0; p < image.pixels(); ++p) {
    for (int k = 0; k < 3; ++k) image.rgba[4 * p + k] = rgb[3 * p + k];
    image.rgba[4 * p + 3] = 1.0f;
  }
  return encodePng("image.png", image, {});
}

}  // namespace surftrace::view
