#include "apps/plot/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "apps/plot/draw.h"

namespace slam::plot {
namespace {

constexpr double kTitleScale = 0.8;
constexpr double kLabelScale = 0.62;
constexpr double kTickScale = 0.52;
const cv::Scalar kGrid(228, 228, 228);

struct Box {
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;
};

// Data -> pixel mapping of one panel.
struct Mapping {
  cv::Rect area;  // Plot area in pixels.
  Box box;        // Data limits.
  cv::Point2d ToPixel(double x, double y) const {
    const double px = area.x + (x - box.x0) / (box.x1 - box.x0) * area.width;
    const double py =
        area.y + area.height - (y - box.y0) / (box.y1 - box.y0) * area.height;
    return {px, py};
  }
};

void Extend(Box* b, bool* any, double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  if (!*any) {
    b->x0 = b->x1 = x;
    b->y0 = b->y1 = y;
    *any = true;
    return;
  }
  b->x0 = std::min(b->x0, x);
  b->x1 = std::max(b->x1, x);
  b->y0 = std::min(b->y0, y);
  b->y1 = std::max(b->y1, y);
}

void Widen(double* lo, double* hi) {
  if (*hi - *lo > 1e-12 * std::max(1.0, std::fabs(*hi))) return;
  const double pad = std::max(0.5, std::fabs(*lo) * 0.1);
  *lo -= pad;
  *hi += pad;
}

struct LegendEntry {
  std::string label;
  cv::Scalar color;
  int thickness = 2;
  bool dashed = false;
  int kind = 0;  // 0 line, 1 circle marker, 2 square marker, 3 colour ramp.
};

void DrawLegendSample(cv::Mat& img, const LegendEntry& e, cv::Point left,
                      int width) {
  const cv::Point2d a(left.x, left.y), b(left.x + width, left.y);
  switch (e.kind) {
    case 0:
      DrawPolyline(img, {a, b}, e.color, e.thickness, e.dashed);
      break;
    case 1:
      cv::circle(img, cv::Point(left.x + width / 2, left.y), 6, e.color,
                 cv::FILLED, cv::LINE_AA);
      break;
    case 2:
      cv::rectangle(img, cv::Rect(left.x + width / 2 - 6, left.y - 6, 12, 12),
                    e.color, cv::FILLED);
      break;
    case 3:
      for (int i = 0; i < width; ++i) {
        cv::line(img, cv::Point(left.x + i, left.y - 3),
                 cv::Point(left.x + i, left.y + 3),
                 ColorMap(static_cast<double>(i) / (width - 1)), 1);
      }
      break;
  }
}

void RenderAxes(const Axes& axes, cv::Mat& img, const cv::Rect& panel) {
  // Colour bar space.
  const ColoredPath* bar = nullptr;
  for (const auto& p : axes.paths) {
    if (!p.x.empty()) {
      bar = &p;
      break;
    }
  }
  const int left = 100, right = bar ? 150 : 30, top = 52, bottom = 68;
  Mapping m;
  m.area = cv::Rect(panel.x + left, panel.y + top, panel.width - left - right,
                    panel.height - top - bottom);

  // Data limits.
  Box box;
  bool any = false;
  for (const auto& l : axes.lines) {
    for (size_t i = 0; i < std::min(l.x.size(), l.y.size()); ++i) {
      Extend(&box, &any, l.x[i], l.y[i]);
    }
  }
  for (const auto& p : axes.paths) {
    for (size_t i = 0; i < std::min(p.x.size(), p.y.size()); ++i) {
      Extend(&box, &any, p.x[i], p.y[i]);
    }
  }
  for (const auto& mk : axes.markers) Extend(&box, &any, mk.x, mk.y);
  for (const auto& h : axes.hlines) {
    if (any && std::isfinite(h.y)) {
      box.y0 = std::min(box.y0, h.y);
      box.y1 = std::max(box.y1, h.y);
    }
  }
  if (!any) box = Box();
  Widen(&box.x0, &box.x1);
  Widen(&box.y0, &box.y1);
  const double px = 0.04 * (box.x1 - box.x0), py = 0.06 * (box.y1 - box.y0);
  box.x0 -= px;
  box.x1 += px;
  box.y0 -= py;
  box.y1 += py;
  if (axes.equal_aspect) {
    const double sx = (box.x1 - box.x0) / m.area.width;
    const double sy = (box.y1 - box.y0) / m.area.height;
    const double s = std::max(sx, sy);
    const double cx = 0.5 * (box.x0 + box.x1), cy = 0.5 * (box.y0 + box.y1);
    box.x0 = cx - 0.5 * s * m.area.width;
    box.x1 = cx + 0.5 * s * m.area.width;
    box.y0 = cy - 0.5 * s * m.area.height;
    box.y1 = cy + 0.5 * s * m.area.height;
  }
  m.box = box;

  // Legend in the emptiest corner.
  std::vector<LegendEntry> entries;
  for (const auto& l : axes.lines) {
    if (!l.label.empty()) {
      entries.push_back({l.label, l.color, l.thickness, l.dashed, 0});
    }
  }
  for (const auto& p : axes.paths) {
    if (!p.label.empty()) entries.push_back({p.label, kBlack, 3, false, 3});
  }
  for (const auto& h : axes.hlines) {
    if (!h.label.empty()) entries.push_back({h.label, h.color, 2, h.dashed, 0});
  }
  for (const auto& mk : axes.markers) {
    if (!mk.label.empty()) {
      entries.push_back({mk.label, mk.color, 2, false, mk.square ? 2 : 1});
    }
  }
  int text_w = 0;
  const int row_h = 24, sample_w = 36;
  for (const auto& e : entries) {
    text_w = std::max(text_w, TextSize(e.label, kTickScale, 1).width);
  }
  const int lw = sample_w + text_w + 30;
  const int lh = row_h * static_cast<int>(entries.size()) + 12;
  // Count data points per corner to pick the emptiest.
  int counts[4] = {0, 0, 0, 0};  // TL, TR, BL, BR
  Mapping local = m;
  local.area = cv::Rect(0, 0, m.area.width, m.area.height);
  auto count_point = [&](double x, double y) {
    const cv::Point2d p = local.ToPixel(x, y);
    const bool l = p.x<lw + 20, r = p.x> m.area.width - lw - 20;
    const bool t = p.y<lh + 20, b = p.y> m.area.height - lh - 20;
    if (t && l) ++counts[0];
    if (t && r) ++counts[1];
    if (b && l) ++counts[2];
    if (b && r) ++counts[3];
  };
  for (const auto& l : axes.lines) {
    for (size_t i = 0; i < std::min(l.x.size(), l.y.size()); ++i) {
      count_point(l.x[i], l.y[i]);
    }
  }
  for (const auto& p : axes.paths) {
    for (size_t i = 0; i < std::min(p.x.size(), p.y.size()); ++i) {
      count_point(p.x[i], p.y[i]);
    }
  }
  for (const auto& h : axes.hlines) {  // They span the whole width.
    count_point(box.x0 + 1e-9 * (box.x1 - box.x0), h.y);
    count_point(box.x1 - 1e-9 * (box.x1 - box.x0), h.y);
  }
  int best = 1;  // Top right unless another corner is emptier.
  for (int c : {0, 3, 2}) {
    if (counts[c] < counts[best]) best = c;
  }
  if (!entries.empty() && counts[best] > 0) {
    // Every corner holds data: make room above it for the legend.
    const double frac = static_cast<double>(lh + 24) / m.area.height;
    box.y1 = box.y0 + (box.y1 - box.y0) / (1.0 - frac);
    if (axes.equal_aspect) {
      const double half =
          0.5 * (box.y1 - box.y0) / m.area.height * m.area.width;
      const double cx = 0.5 * (box.x0 + box.x1);
      box.x0 = cx - half;
      box.x1 = cx + half;
    }
    m.box = box;
    best = 1;
  }

  // Grid and ticks.
  double xstep = 1.0, ystep = 1.0;
  const std::vector<double> xt = NiceTicks(box.x0, box.x1, 8, &xstep);
  const std::vector<double> yt = NiceTicks(box.y0, box.y1, 7, &ystep);
  const int ax0 = m.area.x, ax1 = m.area.x + m.area.width;
  const int ay0 = m.area.y, ay1 = m.area.y + m.area.height;
  for (double x : xt) {
    const int p = static_cast<int>(std::lround(m.ToPixel(x, 0).x));
    cv::line(img, cv::Point(p, ay0), cv::Point(p, ay1), kGrid, 1);
    cv::line(img, cv::Point(p, ay1), cv::Point(p, ay1 + 6), kBlack, 1);
    PutText(img, FormatTick(x, xstep), cv::Point(p, ay1 + 10), kTickScale, 1, 0,
            -1);
  }
  for (double y : yt) {
    const int p = static_cast<int>(std::lround(m.ToPixel(0, y).y));
    cv::line(img, cv::Point(ax0, p), cv::Point(ax1, p), kGrid, 1);
    cv::line(img, cv::Point(ax0 - 6, p), cv::Point(ax0, p), kBlack, 1);
    PutText(img, FormatTick(y, ystep), cv::Point(ax0 - 10, p), kTickScale, 1, 1,
            0);
  }

  // Data, clipped to the plot area.
  cv::Mat area = img(m.area);
  local = m;
  local.area = cv::Rect(0, 0, m.area.width, m.area.height);
  for (const auto& h : axes.hlines) {
    const double py = local.ToPixel(0, h.y).y;
    DrawPolyline(area, {{0.0, py}, {static_cast<double>(m.area.width), py}},
                 h.color, 2, h.dashed);
  }
  for (const auto& p : axes.paths) {
    const size_t n = std::min({p.x.size(), p.y.size(), p.value.size()});
    const double range = p.vmax > p.vmin ? p.vmax - p.vmin : 1.0;
    for (size_t i = 1; i < n; ++i) {
      const double v = 0.5 * (p.value[i - 1] + p.value[i]);
      DrawSegment(area, local.ToPixel(p.x[i - 1], p.y[i - 1]),
                  local.ToPixel(p.x[i], p.y[i]), ColorMap((v - p.vmin) / range),
                  p.thickness);
    }
  }
  for (const auto& l : axes.lines) {
    std::vector<cv::Point2d> pts;
    for (size_t i = 0; i < std::min(l.x.size(), l.y.size()); ++i) {
      if (std::isfinite(l.x[i]) && std::isfinite(l.y[i])) {
        pts.push_back(local.ToPixel(l.x[i], l.y[i]));
      }
    }
    DrawPolyline(area, pts, l.color, l.thickness, l.dashed);
  }
  for (const auto& mk : axes.markers) {
    const cv::Point c = cv::Point(local.ToPixel(mk.x, mk.y));
    if (mk.square) {
      const int h = std::max(1, mk.radius - 1);
      cv::rectangle(area, cv::Rect(c.x - h, c.y - h, 2 * h, 2 * h), mk.color,
                    cv::FILLED);
    } else {
      cv::circle(area, c, mk.radius, mk.color, cv::FILLED, cv::LINE_AA);
    }
  }
  cv::rectangle(img, m.area, kBlack, 1);

  // Title and axis labels.
  PutText(img, axes.title, cv::Point(panel.x + panel.width / 2, panel.y + 14),
          kTitleScale, 2, 0, -1);
  PutText(img, axes.xlabel,
          cv::Point(m.area.x + m.area.width / 2, panel.y + panel.height - 12),
          kLabelScale, 1, 0, 1);
  PutTextVertical(img, axes.ylabel,
                  cv::Point(panel.x + 20, m.area.y + m.area.height / 2),
                  kLabelScale, 1);

  // Colour bar.
  if (bar != nullptr) {
    const int bx = ax1 + 22, bw = 22;
    const int by0 = ay0 + 10, by1 = ay1 - 10;
    for (int y = by0; y <= by1; ++y) {
      const double t = static_cast<double>(by1 - y) / (by1 - by0);
      cv::line(img, cv::Point(bx, y), cv::Point(bx + bw, y), ColorMap(t), 1);
    }
    cv::rectangle(img, cv::Rect(bx, by0, bw, by1 - by0 + 1), kBlack, 1);
    double step = 1.0;
    const double lo = bar->vmin,
                 hi = bar->vmax > bar->vmin ? bar->vmax : bar->vmin + 1.0;
    for (double v : NiceTicks(lo, hi, 6, &step)) {
      const int y = static_cast<int>(
          std::lround(by1 - (v - lo) / (hi - lo) * (by1 - by0)));
      cv::line(img, cv::Point(bx + bw, y), cv::Point(bx + bw + 5, y), kBlack,
               1);
      PutText(img, FormatTick(v, step), cv::Point(bx + bw + 8, y), kTickScale,
              1, -1, 0);
    }
    PutTextVertical(img, bar->colorbar_label,
                    cv::Point(panel.x + panel.width - 16, (by0 + by1) / 2),
                    kLabelScale, 1);
  }

  if (entries.empty()) return;
  const int lx = (best % 2 == 0) ? ax0 + 10 : ax1 - lw - 10;
  const int ly = (best < 2) ? ay0 + 10 : ay1 - lh - 10;
  const cv::Rect legend(lx, ly, lw, lh);
  cv::Mat roi = img(legend);
  cv::Mat white(roi.size(), roi.type(), kWhite);
  cv::addWeighted(roi, 0.15, white, 0.85, 0.0, roi);
  cv::rectangle(img, legend, cv::Scalar(170, 170, 170), 1);
  for (size_t i = 0; i < entries.size(); ++i) {
    const int cy = ly + 6 + row_h * static_cast<int>(i) + row_h / 2;
    DrawLegendSample(img, entries[i], cv::Point(lx + 10, cy), sample_w);
    PutText(img, entries[i].label, cv::Point(lx + 18 + sample_w, cy),
            kTickScale, 1, -1, 0);
  }
}

}  // namespace

cv::Scalar ColorMap(double t) {
  // Jet: blue -> cyan -> yellow -> red.
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  auto ramp = [](double x) { return std::clamp(1.5 - std::fabs(x), 0.0, 1.0); };
  const double r = ramp(4.0 * t - 3.0);
  const double g = ramp(4.0 * t - 2.0);
  const double b = ramp(4.0 * t - 1.0);
  return cv::Scalar(255.0 * b, 255.0 * g, 255.0 * r);
}

std::vector<double> NiceTicks(double lo, double hi, int target, double* step) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) {
    *step = 1.0;
    return ticks;
  }
  const double raw = (hi - lo) / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double nice = norm < 1.5   ? 1.0
                      : norm < 3.5 ? 2.0
                      : norm < 7.5 ? 5.0
                                   : 10.0;
  *step = nice * mag;
  const double first = std::ceil(lo / *step - 1e-9) * *step;
  for (double v = first; v <= hi + 1e-9 * *step; v += *step) {
    ticks.push_back(std::fabs(v) < 1e-12 * *step ? 0.0 : v);
    if (ticks.size() > 100) break;
  }
  return ticks;
}

std::string FormatTick(double value, double step) {
  char buf[64];
  const double a = std::fabs(value);
  if ((a >= 1e6 || (a > 0 && a < 1e-4)) && step < 1e6) {
    std::snprintf(buf, sizeof(buf), "%.3g", value);
    return buf;
  }
  int decimals = 0;
  if (step < 1.0) {
    decimals = static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  }
  std::snprintf(buf, sizeof(buf), "%.*f", std::clamp(decimals, 0, 9), value);
  return buf;
}

cv::Mat RenderFigure(const std::vector<Axes>& panels, int width,
                     int panel_height) {
  cv::Mat img(
      panel_height * static_cast<int>(std::max<size_t>(1, panels.size())),
      width, CV_8UC3, kWhite);
  for (size_t i = 0; i < panels.size(); ++i) {
    RenderAxes(
        panels[i], img,
        cv::Rect(0, panel_height * static_cast<int>(i), width, panel_height));
  }
  return img;
}

}  // namespace slam::plot
