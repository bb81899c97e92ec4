#include "sinew/spectral/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace sinew::spectral {
namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

// Layout, pixels. Rows share one title block and one legend: every row encodes the same way.
constexpr double kWidth = 1200.0;
constexpr double kTitleHeight = 118.0;
constexpr double kRowHeight = 260.0;
constexpr double kBottomMargin = 12.0;
constexpr double kCurveLeft = 78.0;  // room for the tick labels and the rotated unit
constexpr double kCurveRight = 790.0;
constexpr double kBarLeft = 872.0;
constexpr double kBarRight = 1176.0;
constexpr double kPlotTop = 42.0;     // from the row's top: below the row's header line
constexpr double kPlotBottom = 50.0;  // from the row's bottom: tick labels and axis name

// Okabe-Ito colours (distinguishable with the common colour-vision deficiencies), in the x/y/z
// = red/green/blue order animators know from every DCC gizmo.
constexpr const char* kAxisColour[3] = {"#D55E00", "#009E73", "#0072B2"};
constexpr const char* kAxisName[3] = {"x", "y", "z"};
constexpr const char* kText = "#222222";
constexpr const char* kMuted = "#5f5f5f";
constexpr const char* kGrid = "#e6e6e6";
constexpr const char* kAxisLine = "#9a9a9a";
constexpr const char* kFont = "'DejaVu Sans', 'Helvetica Neue', Arial, sans-serif";

std::string number(double value, int decimals) {
  if (std::abs(value) < 0.5 * std::pow(10.0, -decimals)) value = 0.0;  // never "-0"
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

std::string xmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        // XML 1.0 allows no control characters but tab, newline and carriage return.
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n' || c == '\r') out += c;
    }
  }
  return out;
}

// Approximate advance of sans-serif text, to place things beside labels without overlap: code
// points (not bytes) times ~0.58 em, a little wide on purpose.
double textWidth(const std::string& text, double size) {
  int points = 0;
  for (char c : text) points += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return points * size * 0.58;
}

// Axis ticks on 1-2-5 steps. `expand` widens the range to whole steps, so that the data fill the
// axes and both ends carry a label.
struct Ticks {
  double lo = 0.0;
  double hi = 1.0;
  double step = 1.0;
  int decimals = 0;
  std::vector<double> values;
};

Ticks niceTicks(double lo, double hi, int max_count, bool expand, double min_step = 0.0) {
  if (!(hi - lo > 1e-12)) {  // a flat line: a small range around it
    const double pad = std::max(1.0, std::abs(lo) * 0.1);
    lo -= pad;
    hi += pad;
  }
  Ticks ticks;
  const double raw = (hi - lo) / std::max(1, max_count);
  double step = std::pow(10.0, std::floor(std::log10(raw)) - 1.0);
  for (int attempt = 0; attempt < 64; ++attempt) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double s = step * m;
      if (s < min_step) continue;
      const double a = expand ? std::floor(lo / s + 1e-9) * s : std::ceil(lo / s - 1e-9) * s;
      const double b = expand ? std::ceil(hi / s - 1e-9) * s : std::floor(hi / s + 1e-9) * s;
      const int count = static_cast<int>(std::lround((b - a) / s)) + 1;
      if (count <= max_count) {
        ticks.step = s;
        ticks.lo = expand ? a : lo;
        ticks.hi = expand ? b : hi;
        for (int i = 0; i < count; ++i) ticks.values.push_back(a + i * s);
        ticks.decimals = std::max(0, static_cast<int>(-std::floor(std::log10(s) + 1e-9)));
        return ticks;
      }
    }
    step *= 10.0;
  }
  ticks.lo = lo;
  ticks.hi = hi;
  return ticks;
}

// A rectangle of the page showing a data range.
struct Frame {
  double left = 0.0, right = 0.0, top = 0.0, bottom = 0.0;  // pixels
  double x_lo = 0.0, x_hi = 1.0, y_lo = 0.0, y_hi = 1.0;    // data
  double x(double v) const { return left + (v - x_lo) / (x_hi - x_lo) * (right - left); }
  double y(double v) const { return bottom - (v - y_lo) / (y_hi - y_lo) * (bottom - top); }
};

// Appends SVG elements to a string. Coordinates to 0.1 px: finer is invisible and bloats files.
class SvgWriter {
 public:
  std::string out;

  void line(double x1, double y1, double x2, double y2, const char* stroke, double width,
            const std::string& extra = "") {
    out += "<line x1=\"" + px(x1) + "\" y1=\"" + px(y1) + "\" x2=\"" + px(x2) + "\" y2=\"" +
           px(y2) + "\" stroke=\"" + stroke + "\" stroke-width=\"" + number(width, 2) + "\"" +
           extra + "/>\n";
  }
  void rect(double x, double y, double w, double h, const std::string& attributes) {
    out += "<rect x=\"" + px(x) + "\" y=\"" + px(y) + "\" width=\"" + px(std::max(w, 0.0)) +
           "\" height=\"" + px(std::max(h, 0.0)) + "\" " + attributes + "/>\n";
  }
  // anchor: start, middle or end.
  void text(double x, double y, const std::string& content, double size, const char* fill,
            const char* anchor = "start", const std::string& extra = "") {
    out += "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\" font-size=\"" + number(size, 1) +
           "\" fill=\"" + fill + "\" text-anchor=\"" + anchor + "\"" + extra + ">" +
           xmlEscape(content) + "</text>\n";
  }
  void polyline(const Frame& frame, const std::vector<double>& xs, const std::vector<double>& ys,
                const std::string& attributes) {
    out += "<polyline " + attributes + " fill=\"none\" points=\"";
    for (size_t i = 0; i < xs.size(); ++i) {
      if (i > 0) out += ' ';
      out += px(frame.x(xs[i])) + "," + px(frame.y(ys[i]));
    }
    out += "\"/>\n";
  }

  static std::string px(double v) { return number(v, 1); }
};

// Horizontal gridlines and labelled ticks on the left edge, the zero line darker.
void drawYAxis(SvgWriter& svg, const Frame& f, const Ticks& ticks) {
  for (double v : ticks.values) {
    const double y = f.y(v);
    const bool zero = std::abs(v) < 0.5 * ticks.step;
    svg.line(f.left, y, f.right, y, zero ? "#c4c4c4" : kGrid, 1.0);
    svg.line(f.left - 4.0, y, f.left, y, kAxisLine, 1.0);
    svg.text(f.left - 7.0, y + 4.0, number(v, ticks.decimals), 11.0, kMuted, "end");
  }
}

void drawFrameBox(SvgWriter& svg, const Frame& f) {
  svg.line(f.left, f.top, f.left, f.bottom, kAxisLine, 1.0);
  svg.line(f.left, f.bottom, f.right, f.bottom, kAxisLine, 1.0);
}

// Rotation amplitude of a joint: the RMS of its rotation vector's periodic part, radians.
double rotationAmplitude(const MotionSpectrum& spectrum, int joint) {
  double energy = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const int c = spectrum.signals.find(joint, SignalKind::kRotation, axis);
    if (c < 0) continue;
    for (const Harmonic& h : spectrum.series[c].harmonics)
      energy += 0.5 * h.amplitude * h.amplitude;
  }
  return std::sqrt(energy);
}

std::string listNames(const motion::Skeleton& skeleton, const std::vector<int>& joints) {
  std::string out;
  for (size_t i = 0; i < joints.size() && i < 12; ++i) {
    out += (i > 0 ? ", " : "") + skeleton.names[joints[i]];
  }
  if (joints.size() > 12) out += ", ... (" + std::to_string(joints.size()) + " in all)";
  return out;
}

}  // namespace

Status PlotSettings::validate() const {
  if (default_joint_count < 1) {
    return Status::error("default_joint_count must be >= 1, got " +
                         std::to_string(default_joint_count));
  }
  if (max_harmonic < 1) {
    return Status::error("max_harmonic must be >= 1, got " + std::to_string(max_harmonic));
  }
  for (size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].empty())
      return Status::error("joints: name " + std::to_string(i + 1) + " is empty");
    for (size_t j = 0; j < i; ++j) {
      if (joints[j] == joints[i])
        return Status::error("joints: '" + joints[i] + "' is listed twice");
    }
  }
  return {};
}

Result<PlotData> preparePlot(const motion::Skeleton& skeleton, const motion::Clip& clip,
                             const MotionSpectrum& spectrum, const PlotSettings& settings) {
  if (Status status = settings.validate(); !status.ok()) return status;
  const MotionSignals& signals = spectrum.signals;
  if (clip.joint_count != skeleton.jointCount() || clip.frame_count != signals.frame_count ||
      static_cast<int>(spectrum.joint_k.size()) != skeleton.jointCount() ||
      spectrum.series.size() != signals.channels.size() || !(signals.frame_time > 0.0) ||
      !(spectrum.omega0 > 0.0)) {
    return Status::error("the spectrum was not analysed from clip '" + clip.name + "' (" +
                         std::to_string(clip.frame_count) + " frames, " +
                         std::to_string(clip.joint_count) + " joints)");
  }
  std::vector<int> rotating;
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (signals.find(j, SignalKind::kRotation, 0) >= 0) rotating.push_back(j);
  }

  std::vector<int> joints;
  if (settings.joints.empty()) {
    joints = rotating;
    std::stable_sort(joints.begin(), joints.end(), [&spectrum](int a, int b) {
      return rotationAmplitude(spectrum, a) > rotationAmplitude(spectrum, b);
    });
    if (static_cast<int>(joints.size()) > settings.default_joint_count) {
      joints.resize(settings.default_joint_count);
    }
    std::sort(joints.begin(), joints.end());  // skeleton order reads hips, then legs, ...
    if (joints.empty()) return Status::error("no joint rotates in clip '" + clip.name + "'");
  } else {
    for (const std::string& name : settings.joints) {
      const int joint = skeleton.findJoint(name);
      if (joint < 0) {
        return Status::error("unknown joint '" + name +
                             "'; joints that rotate: " + listNames(skeleton, rotating));
      }
      if (signals.find(joint, SignalKind::kRotation, 0) < 0) {
        return Status::error(
            "joint '" + name + "' does not rotate in clip '" + clip.name +
            "': nothing to plot; joints that rotate: " + listNames(skeleton, rotating));
      }
      joints.push_back(joint);
    }
  }

  // The window's frames, as windowFrames() takes them.
  const double dt = signals.frame_time;
  const auto [first, last] = windowFrameRange(spectrum);

  PlotData plot;
  plot.clip_name = clip.name;
  plot.first_frame = first;
  for (int f = first; f <= last; ++f) plot.times_s.push_back(f * dt - spectrum.window.start_s);
  size_t available = 0;
  for (const HarmonicSeries& series : spectrum.series) {
    available = std::max(available, series.harmonics.size());
  }
  plot.harmonics = static_cast<int>(std::min<size_t>(settings.max_harmonic, available));

  for (int joint : joints) {
    PlotRow row;
    row.joint = joint;
    row.name = skeleton.names[joint];
    row.k = spectrum.joint_k[joint];
    if (joint < static_cast<int>(spectrum.joint_errors.size()))
      row.error = spectrum.joint_errors[joint];
    for (int axis = 0; axis < 3; ++axis) {
      const int c = signals.find(joint, SignalKind::kRotation, axis);
      if (c < 0) continue;
      const HarmonicSeries& series = spectrum.series[c];
      const std::vector<Harmonic> terms = series.strongest(row.k);
      PlotChannel channel;
      channel.channel = c;
      channel.axis = axis;
      for (size_t i = 0; i < plot.times_s.size(); ++i) {
        channel.original_deg.push_back(kDegrees * signals.channels[c].values[first + i]);
        channel.model_deg.push_back(kDegrees *
                                    evaluate(series.mean, terms, spectrum.omega0, plot.times_s[i]));
      }
      channel.amplitude_deg.assign(plot.harmonics, 0.0);
      channel.kept.assign(plot.harmonics, false);
      for (const Harmonic& h : series.harmonics) {
        if (h.n >= 1 && h.n <= plot.harmonics)
          channel.amplitude_deg[h.n - 1] = kDegrees * h.amplitude;
      }
      for (const Harmonic& h : terms) {
        if (h.n >= 1 && h.n <= plot.harmonics) channel.kept[h.n - 1] = true;
      }
      row.channels.push_back(std::move(channel));
    }
    plot.rows.push_back(std::move(row));
  }
  return plot;
}

namespace {

// Title block: what was analysed and what the whole model costs.
void drawTitle(SvgWriter& svg, const MotionSpectrum& spectrum, const PlotData& plot) {
  const int frames = static_cast<int>(plot.times_s.size());
  svg.text(24, 34, plot.clip_name, 21.0, kText, "start", " font-weight=\"bold\"");
  std::string line1;
  if (spectrum.stride.found) {
    line1 = "stride " + number(spectrum.period_s, 3) + " s (" + number(1.0 / spectrum.period_s, 2) +
            " Hz, similarity " + number(spectrum.stride.similarity, 2) + ")";
  } else {
    line1 =
        "no stride found: the whole clip is one cycle of " + number(spectrum.period_s, 3) + " s";
  }
  line1 += "  \u00b7  window: frames " + std::to_string(plot.first_frame) + "\u2013" +
           std::to_string(plot.first_frame + frames - 1) + " (" +
           std::to_string(spectrum.window.strides) +
           (spectrum.window.strides == 1 ? " stride" : " strides") + " from " +
           number(spectrum.window.start_s, 3) + " s)  \u00b7  " +
           std::to_string(spectrum.samples_per_stride) + " samples per stride";
  int k_lo = std::numeric_limits<int>::max();
  int k_hi = 0;
  for (const SignalChannel& channel : spectrum.signals.channels) {
    k_lo = std::min(k_lo, spectrum.joint_k[channel.joint]);
    k_hi = std::max(k_hi, spectrum.joint_k[channel.joint]);
  }
  const std::string k_text =
      k_hi <= k_lo ? "K = " + std::to_string(k_hi) + " per joint"
                   : "K = " + std::to_string(k_lo) + "\u2013" + std::to_string(k_hi) + " per joint";
  const std::string line2 = k_text + "  \u00b7  " + std::to_string(spectrum.coefficientCount()) +
                            " coefficients  \u00b7  model error over the window: " +
                            number(spectrum.total.rot_err_deg_rms, 2) + "\u00b0 RMS, " +
                            number(spectrum.total.rot_err_deg_max, 1) + "\u00b0 max; position " +
                            number(spectrum.total.pos_err_cm_mean, 2) + " cm mean, " +
                            number(spectrum.total.pos_err_cm_max, 2) + " cm max";
  svg.text(24, 57, line1, 13.0, kText);
  svg.text(24, 76, line2, 13.0, kText);
}

// One legend for every row.
void drawLegend(SvgWriter& svg) {
  double x = 24.0;
  const double ly = 102.0;
  const auto legendText = [&](const std::string& label, double gap_after) {
    svg.text(x, ly + 4.0, label, 12.0, kMuted);
    x += textWidth(label, 12.0) + gap_after;
  };
  for (int axis = 0; axis < 3; ++axis) {
    svg.rect(x, ly - 5.0, 14.0, 10.0, std::string("fill=\"") + kAxisColour[axis] + "\"");
    x += 19.0;
    legendText(kAxisName[axis], 14.0);
  }
  x += 12.0;
  svg.line(x, ly, x + 30.0, ly, "#444444", 4.0,
           " stroke-opacity=\"0.35\" stroke-linecap=\"round\"");
  x += 36.0;
  legendText("original", 18.0);
  svg.line(x, ly, x + 30.0, ly, "#444444", 1.8, " stroke-dasharray=\"6 4\"");
  x += 36.0;
  legendText("model (K harmonics)", 30.0);
  svg.rect(x, ly - 6.0, 9.0, 12.0, "fill=\"#555555\" stroke=\"#555555\" stroke-width=\"1\"");
  x += 14.0;
  legendText("harmonic kept", 16.0);
  svg.rect(x + 0.5, ly - 5.5, 8.0, 11.0,
           "fill=\"#ffffff\" stroke=\"#555555\" stroke-width=\"1\" stroke-opacity=\"0.7\"");
  x += 14.0;
  legendText("discarded", 28.0);
  legendText("curves: rotation vector from the mean pose, local axes", 0.0);
}

// A row's header: the joint, K and what keeping K costs it.
void drawRowHeader(SvgWriter& svg, const PlotRow& row, double top) {
  svg.line(16, top + 0.5, kWidth - 16, top + 0.5, "#d0d0d0", 1.0);
  const std::string stats = "K = " + std::to_string(row.k) + "  \u00b7  angle error " +
                            number(row.error.rot_err_deg_rms, 2) + "\u00b0 RMS, " +
                            number(row.error.rot_err_deg_max, 2) + "\u00b0 max  \u00b7  position " +
                            number(row.error.pos_err_cm_mean, 2) + " cm mean, " +
                            number(row.error.pos_err_cm_max, 2) + " cm max";
  // One text element: the renderer places the stats after the name, whatever its font.
  svg.out += "<text x=\"24\" y=\"" + SvgWriter::px(top + 25) + "\" fill=\"" + kText +
             "\"><tspan font-size=\"15\" font-weight=\"bold\">" + xmlEscape(row.name) +
             "</tspan><tspan dx=\"14\" font-size=\"12.5\" fill=\"" + kMuted + "\">" +
             xmlEscape(stats) + "</tspan></text>\n";
  svg.text(kBarLeft, top + 25, "harmonic amplitudes", 12.5, kMuted);
}

// How many y ticks a row's plots aim for.
int rowTickCount(const Frame& frame) {
  return std::max(3, static_cast<int>((frame.bottom - frame.top) / 32.0));
}

// A row's left half: the curves against the clip's frame numbers.
void drawCurves(SvgWriter& svg, const MotionSpectrum& spectrum, const PlotData& plot,
                const PlotRow& row, Frame curves) {
  const int frames = static_cast<int>(plot.times_s.size());
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const PlotChannel& channel : row.channels) {
    for (double v : channel.original_deg) lo = std::min(lo, v), hi = std::max(hi, v);
    for (double v : channel.model_deg) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  if (!(lo <= hi)) lo = hi = 0.0;
  const Ticks y_ticks = niceTicks(lo, hi, rowTickCount(curves), true);
  const double first = plot.first_frame;
  const double last = plot.first_frame + std::max(frames - 1, 1);
  const int x_count = static_cast<int>((curves.right - curves.left) / 56.0);
  const Ticks x_ticks = niceTicks(first, last, x_count, false, 1.0);
  curves.x_lo = first;
  curves.x_hi = last;
  curves.y_lo = y_ticks.lo;
  curves.y_hi = y_ticks.hi;
  for (double v : x_ticks.values) {
    const double xp = curves.x(v);
    svg.line(xp, curves.top, xp, curves.bottom, kGrid, 1.0);
    svg.line(xp, curves.bottom, xp, curves.bottom + 4.0, kAxisLine, 1.0);
    svg.text(xp, curves.bottom + 17.0, number(v, 0), 11.0, kMuted, "middle");
  }
  drawYAxis(svg, curves, y_ticks);
  // Stride boundaries inside a multi-stride window.
  for (int s = 1; s < spectrum.window.strides; ++s) {
    const double t = spectrum.window.start_s + s * spectrum.period_s;
    const double xp = curves.x(t / spectrum.signals.frame_time);
    svg.line(xp, curves.top, xp, curves.bottom, "#9a9a9a", 1.0, " stroke-dasharray=\"2 3\"");
  }
  drawFrameBox(svg, curves);
  svg.text((curves.left + curves.right) / 2, curves.bottom + 36.0, "frame", 12.0, kMuted, "middle");
  const double mid_y = (curves.top + curves.bottom) / 2;
  svg.text(28, mid_y, "degrees", 12.0, kMuted, "middle",
           " transform=\"rotate(-90 28 " + number(mid_y, 1) + ")\"");
  std::vector<double> xs(frames);
  for (int i = 0; i < frames; ++i) xs[i] = plot.first_frame + i;
  // Originals first (wide and pale), then every model on top, so that no original hides a
  // model.
  for (const PlotChannel& channel : row.channels) {
    svg.polyline(curves, xs, channel.original_deg,
                 std::string("class=\"original\" stroke=\"") + kAxisColour[channel.axis] +
                     "\" stroke-width=\"4\" stroke-opacity=\"0.35\" stroke-linejoin=\"round\" "
                     "stroke-linecap=\"round\"");
  }
  for (const PlotChannel& channel : row.channels) {
    svg.polyline(curves, xs, channel.model_deg,
                 std::string("class=\"model\" stroke=\"") + kAxisColour[channel.axis] +
                     "\" stroke-width=\"1.8\" stroke-dasharray=\"6 4\" stroke-linejoin=\"round\"");
  }
}

// A row's right half: the amplitude of each harmonic, x y z side by side, kept ones filled.
void drawBars(SvgWriter& svg, const PlotData& plot, const PlotRow& row, Frame bars) {
  double most = 0.0;
  for (const PlotChannel& channel : row.channels) {
    for (double a : channel.amplitude_deg) most = std::max(most, a);
  }
  const Ticks a_ticks = niceTicks(0.0, std::max(most, 1e-3), rowTickCount(bars), true);
  bars.x_lo = 0.0;
  bars.x_hi = std::max(plot.harmonics, 1);
  bars.y_lo = 0.0;
  bars.y_hi = a_ticks.hi;
  drawYAxis(svg, bars, a_ticks);
  const double group = (bars.right - bars.left) / std::max(plot.harmonics, 1);
  const double bar = std::min(9.0, group * 0.8 / 3.0);
  // Label every harmonic when they fit, else every other one.
  const int label_every = group >= 18.0 ? 1 : 2;
  for (int n = 1; n <= plot.harmonics; ++n) {
    const double centre = bars.left + (n - 0.5) * group;
    if ((n - 1) % label_every == 0) {
      svg.text(centre, bars.bottom + 17.0, std::to_string(n), 11.0, kMuted, "middle");
    }
    for (const PlotChannel& channel : row.channels) {
      const double a = channel.amplitude_deg[n - 1];
      const double x0 = centre + (channel.axis - 1.5) * bar;
      const double y0 = bars.y(a);
      const std::string colour = kAxisColour[channel.axis];
      if (channel.kept[n - 1]) {
        svg.rect(x0, y0, bar, bars.bottom - y0, "class=\"kept\" fill=\"" + colour + "\"");
      } else {
        // Hollow: the outline drawn inside the bar's extent, so that it is the same size.
        svg.rect(x0 + 0.6, y0 + 0.6, bar - 1.2, bars.bottom - y0 - 0.6,
                 "class=\"discarded\" fill=\"#ffffff\" stroke=\"" + colour +
                     "\" stroke-width=\"1.2\" stroke-opacity=\"0.75\"");
      }
    }
  }
  drawFrameBox(svg, bars);
  svg.text((bars.left + bars.right) / 2, bars.bottom + 36.0, "harmonic n (\u00d7 stride frequency)",
           12.0, kMuted, "middle");
  const double bar_mid = (bars.top + bars.bottom) / 2;
  const double label_x = kBarLeft - 50.0;
  svg.text(label_x, bar_mid, "degrees", 12.0, kMuted, "middle",
           " transform=\"rotate(-90 " + number(label_x, 1) + " " + number(bar_mid, 1) + ")\"");
}

// One joint's row: header, curves on the left, harmonic bars on the right.
void drawRow(SvgWriter& svg, const MotionSpectrum& spectrum, const PlotData& plot, int r) {
  const PlotRow& row = plot.rows[r];
  const double top = kTitleHeight + r * kRowHeight;
  svg.out += "<g class=\"row\">\n";
  drawRowHeader(svg, row, top);
  Frame curves;
  curves.left = kCurveLeft;
  curves.right = kCurveRight;
  curves.top = top + kPlotTop;
  curves.bottom = top + kRowHeight - kPlotBottom;
  drawCurves(svg, spectrum, plot, row, curves);
  Frame bars;
  bars.left = kBarLeft;
  bars.right = kBarRight;
  bars.top = curves.top;
  bars.bottom = curves.bottom;
  drawBars(svg, plot, row, bars);
  svg.out += "</g>\n";
}

}  // namespace

std::string renderPlotSvg(const MotionSpectrum& spectrum, const PlotData& plot) {
  const int rows = static_cast<int>(plot.rows.size());
  const double height = kTitleHeight + rows * kRowHeight + kBottomMargin;
  SvgWriter svg;
  svg.out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg.out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" +
             number(kWidth, 0) + "\" height=\"" + number(height, 0) + "\" viewBox=\"0 0 " +
             number(kWidth, 0) + " " + number(height, 0) + "\">\n";
  svg.out += "<title>" + xmlEscape(plot.clip_name) + ": harmonic model</title>\n";
  svg.rect(0, 0, kWidth, height, "fill=\"#ffffff\"");
  svg.out += std::string("<g font-family=\"") + kFont + "\">\n";
  drawTitle(svg, spectrum, plot);
  drawLegend(svg);
  for (int r = 0; r < rows; ++r) drawRow(svg, spectrum, plot, r);
  svg.out += "</g>\n</svg>\n";
  return svg.out;
}

Result<std::string> plotSvg(const motion::Skeleton& skeleton, const motion::Clip& clip,
                            const MotionSpectrum& spectrum, const PlotSettings& settings) {
  Result<PlotData> plot = preparePlot(skeleton, clip, spectrum, settings);
  if (!plot.ok()) return plot.status();
  return renderPlotSvg(spectrum, plot.value());
}

}  // namespace sinew::spectral
