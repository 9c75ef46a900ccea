#include "tools/render/plot.h"

#include "core/math_constants.h"
#include "core/mesh.h"
#include "tools/render/image.h"

#include <cairo.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

namespace jetshell {
namespace {

/// The colours of series that name none (gnuplot's default sequence, which earlier plots used).
constexpr const char* kDefaultColours[] = {"#9400d3", "#009e73", "#56b4e9", "#e69f00",
                                           "#f0e442", "#0072b2", "#e51e10", "#000000"};

bool isHexColour(const std::string& c) {
  if (c.size() != 7 || c[0] != '#') return false;
  for (std::size_t i = 1; i < 7; ++i)
    if (!std::isxdigit(static_cast<unsigned char>(c[i]))) return false;
  return true;
}

struct Colour {
  double r, g, b;
};

Colour parseColour(const std::string& hex) {
  const unsigned long v = std::stoul(hex.substr(1), nullptr, 16);
  return {((v >> 16) & 0xff) / 255.0, ((v >> 8) & 0xff) / 255.0, (v & 0xff) / 255.0};
}

/// A value an axis can show: finite, and positive on a log axis.
bool drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); }

/// One axis: its range (rounded out to ticks), whether it is logarithmic, and its ticks.
struct Axis {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  std::vector<double> ticks;
  int digits = 6;  // significant digits of the tick labels

  bool accepts(double v) const { return drawable(v, log); }
  /// 0 at lo, 1 at hi.
  double unit(double v) const {
    return log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
  }
};

/// 1, 2 or 5 times a power of ten, near span / count.
double niceStep(double span, int count) {
  const double raw = span / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / power;
  return (m < 1.5 ? 1.0 : m < 3.0 ? 2.0 : m < 7.0 ? 5.0 : 10.0) * power;
}

/// The axis that holds [lo, hi] (the data's range; lo > hi when there is no data).
Axis makeAxis(double lo, double hi, bool log) {
  Axis a;
  a.log = log;
  if (log) {
    if (!(lo <= hi)) lo = 1.0, hi = 10.0;
    const double first = std::floor(std::log10(lo));
    double last = std::ceil(std::log10(hi));
    if (last <= first) last = first + 1.0;
    a.lo = std::pow(10.0, first);
    a.hi = std::pow(10.0, last);
    const int stride = std::max(1, static_cast<int>(std::ceil((last - first) / 8.0)));
    for (double e = first; e <= last; e += stride) {
      a.ticks.push_back(std::pow(10.0, e));
      if (last - first <= 2.0 && e < last) {
        a.ticks.push_back(2.0 * std::pow(10.0, e));
        a.ticks.push_back(5.0 * std::pow(10.0, e));
      }
    }
    a.digits = 3;
    return a;
  }
  if (!(lo <= hi)) lo = 0.0, hi = 1.0;
  // Values beyond ±1e300 would overflow the span; such a plot shows nothing readable anyway.
  lo = std::clamp(lo, -1e300, 1e300);
  hi = std::clamp(hi, -1e300, 1e300);
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  const double step = niceStep(hi - lo, 6);
  a.lo = std::floor(lo / step) * step;
  a.hi = std::ceil(hi / step) * step;
  const int count = std::min(50, static_cast<int>(std::lround((a.hi - a.lo) / step)));
  for (int k = 0; k <= count; ++k) {
    const double v = a.lo + k * step;
    a.ticks.push_back(std::abs(v) < 1e-9 * step ? 0.0 : v);
  }
  const double magnitude = std::max(std::abs(a.lo), std::abs(a.hi));
  a.digits = std::clamp(static_cast<int>(std::ceil(std::log10(magnitude / step))) + 1, 1, 15);
  return a;
}

std::string tickLabel(double v, int digits) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

double textWidth(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  return e.x_advance;
}

void setDash(cairo_t* cr, int dashType, double lineWidth) {
  const int kind = dashType <= 1 ? 0 : (dashType - 2) % 4 + 1;
  const double u = std::max(1.0, lineWidth);
  const double patterns[5][6] = {{0}, {6 * u, 4 * u}, {1 * u, 3 * u}, {6 * u, 3 * u, 1 * u, 3 * u},
                                 {6 * u, 3 * u, 1 * u, 3 * u, 1 * u, 3 * u}};
  const int lengths[5] = {0, 2, 2, 4, 6};
  cairo_set_dash(cr, patterns[kind], lengths[kind], 0.0);
}

/// The pixel rectangle of the data and the mapping into it.
struct Frame {
  double x0, y0, x1, y1;  // left, top, right, bottom
  const Axis *x, *y;
  double px(double v) const { return std::clamp(x0 + (x1 - x0) * x->unit(v), -1e5, 1e5); }
  double py(double v) const { return std::clamp(y1 - (y1 - y0) * y->unit(v), -1e5, 1e5); }
};

void drawSeries(cairo_t* cr, const Frame& f, const PlotSeries& s, const Colour& c, double lineWidth) {
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
  const bool lines = s.style != "points", points = s.style != "lines";
  if (lines) {
    bool down = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.x->accepts(s.x[i]) || !f.y->accepts(s.y[i])) {
        down = false;
        continue;
      }
      (down ? cairo_line_to : cairo_move_to)(cr, f.px(s.x[i]), f.py(s.y[i]));
      down = true;
    }
    cairo_set_line_width(cr, lineWidth);
    setDash(cr, s.dashType, lineWidth);
    cairo_stroke(cr);
  }
  if (points) {
    const double radius = lines ? 1.4 * lineWidth : 1.8 * lineWidth;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!f.x->accepts(s.x[i]) || !f.y->accepts(s.y[i])) continue;
      cairo_new_sub_path(cr);
      cairo_arc(cr, f.px(s.x[i]), f.py(s.y[i]), radius, 0.0, kTwoPi);
    }
    cairo_fill(cr);
  }
}

void validate(const PlotSpec& spec, const std::string& where) {
  if (spec.series.empty()) throw InputError(where + ": nothing to plot (no series)");
  if (spec.width < kMinPlotSize || spec.width > kMaxPlotSize || spec.height < kMinPlotSize ||
      spec.height > kMaxPlotSize)
    throw InputError(where + ": plot size " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " is outside " + std::to_string(kMinPlotSize) + ".." + std::to_string(kMaxPlotSize) + " pixels");
  if (spec.series.size() > kMaxPlotSeries)
    throw InputError(where + ": " + std::to_string(spec.series.size()) + " series (at most " +
                     std::to_string(kMaxPlotSeries) + ")");
  std::size_t points = 0;
  for (const PlotSeries& p : spec.series) {
    const std::string name = "series '" + drawableText(p.label) + "'";
    if (p.x.size() != p.y.size())
      throw InputError(where + ": " + name + " has " + std::to_string(p.x.size()) + " x values and " +
                       std::to_string(p.y.size()) + " y values");
    if (p.style != "lines" && p.style != "points" && p.style != "linespoints")
      throw InputError(where + ": " + name + " has style '" + drawableText(p.style) +
                       "' (expected lines, points or linespoints)");
    if (!p.color.empty() && !isHexColour(p.color))
      throw InputError(where + ": " + name + " has colour '" + drawableText(p.color) + "' (expected #rrggbb)");
    points += p.x.size();
  }
  if (points > kMaxPlotPoints)
    throw InputError(where + ": " + std::to_string(points) + " points (at most " + std::to_string(kMaxPlotPoints) +
                     ")");
}

}  // namespace

std::string drawableText(const std::string& text) {
  static const char* kReplacement = "\xEF\xBF\xBD";
  static const std::uint32_t kSmallest[5] = {0, 0, 0x80, 0x800, 0x10000};  // shortest form per length
  std::string out;
  std::size_t i = 0, kept = 0;
  while (i < text.size() && kept < kMaxPlotText) {
    ++kept;
    const auto c = static_cast<unsigned char>(text[i]);
    const int length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
    bool valid = length > 0 && i + static_cast<std::size_t>(length) <= text.size();
    std::uint32_t code = length == 1 ? c : c & (0xffu >> (length + 1));
    for (int k = 1; valid && k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + static_cast<std::size_t>(k)]);
      valid = (next & 0xc0) == 0x80;
      code = (code << 6) | (next & 0x3fu);
    }
    if (valid && length > 1)
      valid = code >= kSmallest[length] && code <= 0x10ffff && !(code >= 0xd800 && code <= 0xdfff);
    if (!valid) {
      out += kReplacement;
      ++i;
    } else if (code < 0x20 || (code >= 0x7f && code < 0xa0)) {
      out += ' ';
      i += static_cast<std::size_t>(length);
    } else {
      out.append(text, i, static_cast<std::size_t>(length));
      i += static_cast<std::size_t>(length);
    }
  }
  return out;
}

std::vector<std::uint8_t> drawPlot(const PlotSpec& spec, const std::string& where) {
  validate(spec, where);
  const int width = spec.width, height = spec.height;

  // The data's range on each axis (only what the axis can show: finite, and positive on a log axis).
  double xLo = HUGE_VAL, xHi = -HUGE_VAL, yLo = HUGE_VAL, yHi = -HUGE_VAL;
  for (const PlotSeries& s : spec.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!drawable(s.x[i], spec.logX) || !drawable(s.y[i], spec.logY)) continue;
      xLo = std::min(xLo, s.x[i]), xHi = std::max(xHi, s.x[i]);
      yLo = std::min(yLo, s.y[i]), yHi = std::max(yHi, s.y[i]);
    }
  const Axis xAxis = makeAxis(xLo, xHi, spec.logX), yAxis = makeAxis(yLo, yHi, spec.logY);

  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), cairo_surface_destroy);
  Context context(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  const double font = std::clamp(std::min(width / 70.0, height / 45.0), 8.0, 16.0);
  const double lineWidth = std::clamp(font / 6.5, 1.0, 2.5);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, font);

  std::vector<std::string> xTicks, yTicks;
  double yTickWidth = 0.0;
  for (double t : xAxis.ticks) xTicks.push_back(tickLabel(t, xAxis.digits));
  for (double t : yAxis.ticks) {
    yTicks.push_back(tickLabel(t, yAxis.digits));
    yTickWidth = std::max(yTickWidth, textWidth(cr, yTicks.back()));
  }
  std::vector<std::string> labels;
  double labelWidth = 0.0;
  for (const PlotSeries& s : spec.series) {
    labels.push_back(drawableText(s.label));
    labelWidth = std::max(labelWidth, textWidth(cr, labels.back()));
  }
  const std::string title = drawableText(spec.title), xLabel = drawableText(spec.xLabel),
                    yLabel = drawableText(spec.yLabel);

  // Layout: title on top, y label and tick labels on the left, x ones below, the key outside on the right.
  const double sample = 3.0 * font;
  const double keyWidth = std::min(0.35 * width, sample + 1.5 * font + labelWidth);
  Frame f;
  f.x = &xAxis;
  f.y = &yAxis;
  f.x0 = std::min(0.25 * width, (yLabel.empty() ? 0.5 : 2.0) * font + yTickWidth + 0.8 * font);
  f.x1 = width - keyWidth - font;
  f.y0 = (title.empty() ? 1.0 : 2.6) * font;
  f.y1 = height - (xLabel.empty() ? 2.0 : 3.6) * font;

  // Grid, frame, ticks.
  cairo_set_line_width(cr, 1.0);
  cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  const double dotted[] = {2.0, 2.0};
  cairo_set_dash(cr, dotted, 2, 0.0);
  for (double t : xAxis.ticks) {
    cairo_move_to(cr, std::round(f.px(t)) + 0.5, f.y0);
    cairo_line_to(cr, std::round(f.px(t)) + 0.5, f.y1);
  }
  for (double t : yAxis.ticks) {
    cairo_move_to(cr, f.x0, std::round(f.py(t)) + 0.5);
    cairo_line_to(cr, f.x1, std::round(f.py(t)) + 0.5);
  }
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, std::round(f.x0) + 0.5, std::round(f.y0) + 0.5, std::round(f.x1 - f.x0), std::round(f.y1 - f.y0));
  cairo_stroke(cr);
  for (std::size_t k = 0; k < xAxis.ticks.size(); ++k) {
    const double x = f.px(xAxis.ticks[k]);
    cairo_move_to(cr, x - 0.5 * textWidth(cr, xTicks[k]), f.y1 + 1.3 * font);
    cairo_show_text(cr, xTicks[k].c_str());
  }
  for (std::size_t k = 0; k < yAxis.ticks.size(); ++k) {
    const double y = f.py(yAxis.ticks[k]);
    cairo_move_to(cr, f.x0 - 0.4 * font - textWidth(cr, yTicks[k]), y + 0.35 * font);
    cairo_show_text(cr, yTicks[k].c_str());
  }
  // Titles: centred where they fit, otherwise from the left edge (and cut by the picture's edge).
  auto centred = [&](const std::string& text, double middle, double room) {
    const double w = textWidth(cr, text);
    return w <= room ? middle - 0.5 * w : middle - 0.5 * room;
  };
  if (!title.empty()) {
    cairo_move_to(cr, std::max(0.5 * font, centred(title, 0.5 * width, width - font)), 1.6 * font);
    cairo_show_text(cr, title.c_str());
  }
  if (!xLabel.empty()) {
    cairo_move_to(cr, centred(xLabel, 0.5 * (f.x0 + f.x1), f.x1 - f.x0), f.y1 + 2.9 * font);
    cairo_show_text(cr, xLabel.c_str());
  }
  if (!yLabel.empty()) {
    cairo_save(cr);
    // Rotated text runs upwards from its start, which sits below the frame's middle by half the text's length.
    const double start = 0.5 * (f.y0 + f.y1) + 0.5 * std::min(textWidth(cr, yLabel), f.y1 - f.y0);
    cairo_move_to(cr, 1.3 * font, start);
    cairo_rotate(cr, -0.5 * kPi);
    cairo_show_text(cr, yLabel.c_str());
    cairo_restore(cr);
  }

  // The curves, clipped to the frame, then the key.
  std::vector<Colour> colours;
  std::size_t next = 0;
  for (const PlotSeries& s : spec.series)
    colours.push_back(parseColour(s.color.empty() ? kDefaultColours[next++ % 8] : s.color));
  cairo_save(cr);
  cairo_rectangle(cr, f.x0, f.y0, f.x1 - f.x0, f.y1 - f.y0);
  cairo_clip(cr);
  for (std::size_t k = 0; k < spec.series.size(); ++k) drawSeries(cr, f, spec.series[k], colours[k], lineWidth);
  cairo_restore(cr);

  cairo_save(cr);
  const double keyX = width - keyWidth;
  cairo_rectangle(cr, keyX, 0, keyWidth, height);
  cairo_clip(cr);
  const double row = 1.4 * font;
  const std::size_t rows = static_cast<std::size_t>(std::max(0.0, std::floor((f.y1 - f.y0) / row)));
  const std::size_t shown = spec.series.size() <= rows ? spec.series.size() : (rows > 0 ? rows - 1 : 0);
  const Axis unitAxis = makeAxis(0.0, 1.0, false);  // a key sample spans [0, 1] of its own little frame
  for (std::size_t k = 0; k < shown; ++k) {
    const double y = f.y0 + (static_cast<double>(k) + 0.7) * row;
    PlotSeries mark("", {}, {}, spec.series[k].style, "", spec.series[k].dashType);
    Frame key{keyX, y, keyX + sample, y, &unitAxis, &unitAxis};
    mark.x = spec.series[k].style == "points" ? std::vector<double>{0.5} : std::vector<double>{0.0, 1.0};
    if (spec.series[k].style == "linespoints") mark.x = {0.0, 0.5, 1.0};
    mark.y.assign(mark.x.size(), 0.0);
    drawSeries(cr, key, mark, colours[k], lineWidth);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, keyX + sample + 0.5 * font, y + 0.35 * font);
    cairo_show_text(cr, labels[k].c_str());
  }
  if (shown < spec.series.size()) {
    const std::string more = "+" + std::to_string(spec.series.size() - shown) + " more";
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, keyX + 0.5 * font, f.y0 + (static_cast<double>(shown) + 0.7) * row + 0.35 * font);
    cairo_show_text(cr, more.c_str());
  }
  cairo_restore(cr);

  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS)
    throw InputError(where + ": drawing failed (" + cairo_status_to_string(cairo_status(cr)) + ")");
  cairo_surface_flush(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint32_t pixel;
      std::memcpy(&pixel, data + static_cast<std::ptrdiff_t>(y) * stride + 4 * x, 4);
      std::uint8_t* out = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
      out[0] = static_cast<std::uint8_t>(pixel >> 16);
      out[1] = static_cast<std::uint8_t>(pixel >> 8);
      out[2] = static_cast<std::uint8_t>(pixel);
    }
  return rgb;
}

void plotPng(const PlotSpec& spec, const std::string& pngPath) {
  writePngRgb8(pngPath, spec.width, spec.height, drawPlot(spec, pngPath));
}

}  // namespace jetshell
