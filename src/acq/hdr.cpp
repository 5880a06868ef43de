#include "acq/hdr.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/error.h"

namespace acq {

void HdrOptions::Check() const {
  if (!(saturation_fraction > 0 && saturation_fraction <= 1))
    throw UserError("hdr", "saturation_fraction must be in (0, 1]");
  if (!(noise_floor_dn >= 0 && black_level_dn >= 0))
    throw UserError("hdr", "the black level and the noise floor must be >= 0 counts");
}

std::vector<float> HdrImage::Grey() const {
  const std::size_t n = std::size_t(width) * std::size_t(height);
  if (channels == 1) return radiance;
  std::vector<float> grey(n);
  for (std::size_t i = 0; i < n; ++i)
    grey[i] = (radiance[i] + radiance[n + i] + radiance[2 * n + i]) / 3;
  return grey;
}

HdrImage MergeBracket(const std::vector<Frame>& frames, const HdrOptions& options) {
  options.Check();
  if (frames.empty()) throw UserError("hdr", "no frames to merge");
  HdrImage out;
  out.width = frames[0].width;
  out.height = frames[0].height;
  for (const Frame& f : frames) {
    if (f.width != out.width || f.height != out.height)
      throw UserError("hdr", "frames of different sizes in one bracket (" +
                                 std::to_string(f.width) + "x" + std::to_string(f.height) + ")");
    if (!(f.exposure_us > 0)) throw UserError("hdr", "a frame without an exposure time");
    if (CfaOf(f.pixel_format) != CfaOf(frames[0].pixel_format))
      throw UserError("hdr",
                      std::string("frames of different colour filters in one bracket (") +
                          PixelFormatName(frames[0].pixel_format) + " and " +
                          PixelFormatName(f.pixel_format) + ")",
                      "take a pose's bracket in one pixel format");
  }
  out.cfa = CfaOf(frames[0].pixel_format);
  // Shortest first: the fallback for pixels saturated everywhere is the shortest frame.
  std::vector<const Frame*> sorted;
  for (const Frame& f : frames) sorted.push_back(&f);
  std::sort(sorted.begin(), sorted.end(),
            [](const Frame* a, const Frame* b) { return a->exposure_us < b->exposure_us; });
  struct Scale {
    const std::uint16_t* pixels;
    double saturated, per_count;
  };
  std::vector<Scale> scales;
  for (const Frame* f : sorted) {
    const double gain = std::pow(10.0, f->gain_db / 20);
    scales.push_back({f->pixels.data(), options.saturation_fraction * f->MaxValue(),
                      1.0 / (f->exposure_us * gain)});
  }
  const std::size_t n = std::size_t(out.width) * std::size_t(out.height);
  out.radiance.assign(n, 0.f);
  out.flag.assign(n, kHdrOk);
  const double black = options.black_level_dn;
#pragma omp parallel for
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
    auto s = scales.rbegin();  // the longest frame below saturation
    while (s != scales.rend() && s->pixels[i] >= s->saturated) ++s;
    const bool saturated = s == scales.rend();
    if (saturated) s = std::prev(scales.rend());  // the shortest
    out.radiance[i] = float(std::max(0.0, s->pixels[i] - black) * s->per_count);
    out.flag[i] = saturated ? kHdrSaturated : kHdrOk;
  }
  return out;
}

namespace {

double Percentile(std::vector<std::uint16_t> v, double p) {
  const std::size_t k = std::min(v.size() - 1, std::size_t(p * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

}  // namespace

std::vector<double> ChooseBracket(Camera& camera, CameraSettings settings, const HdrOptions& hdr,
                                  const AutoBracketOptions& o) {
  hdr.Check();
  // Shorten the probe until its brightest pixels are below saturation.
  Frame probe;
  double bright = 0;
  for (;;) {
    camera.Apply(settings);
    probe = camera.Grab();
    bright = Percentile(probe.pixels, 0.9999) - hdr.black_level_dn;
    if (bright < hdr.saturation_fraction * probe.MaxValue() - hdr.black_level_dn) break;
    if (settings.exposure_us <= o.min_exposure_us)
      throw UserError("camera " + camera.Describe(),
                      "the scene saturates even at the shortest exposure (" +
                          std::to_string(o.min_exposure_us) + " us)",
                      "lower the light level or the gain");
    settings.exposure_us = std::max(o.min_exposure_us, settings.exposure_us / 8);
  }
  const double t0 = settings.exposure_us;
  const double full = probe.MaxValue() - hdr.black_level_dn;
  const double shortest = std::clamp(t0 * o.headroom * full / std::max(bright, 1.0),
                                     o.min_exposure_us, o.max_exposure_us);
  // The dark end is read from a frame at the shortest exposure itself: the first probe may be
  // so dark (or so short) that its darkest pixels are all zero.
  settings.exposure_us = shortest;
  camera.Apply(settings);
  const Frame at_shortest = camera.Grab();
  const double dark =
      std::max(0.5, Percentile(at_shortest.pixels, o.dark_percentile) - hdr.black_level_dn);
  // The exposure that lifts the dark end to 10x the noise floor.
  const double longest = std::clamp(shortest * 10 * std::max(hdr.noise_floor_dn, 1.0) / dark,
                                    shortest, o.max_exposure_us);
  std::vector<double> exposures{shortest};
  while (exposures.back() < longest && int(exposures.size()) < o.max_frames)
    exposures.push_back(std::min(exposures.back() * o.step, o.max_exposure_us));
  return exposures;
}

std::vector<Frame> CaptureBracket(Camera& camera, CameraSettings settings,
                                  const std::vector<double>& exposures_us) {
  std::vector<Frame> frames;
  for (double t : exposures_us) {
    settings.exposure_us = t;
    camera.Apply(settings);
    frames.push_back(camera.Grab());
  }
  return frames;
}

}  // namespace acq
