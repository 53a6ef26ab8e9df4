#include "camera_server/core/format_negotiation.hpp"

#include <cmath>
#include <sstream>

namespace stereoball::camera_server {
namespace {

bool fits(uint32_t v, uint32_t lo, uint32_t hi, uint32_t step) {
  if (v < lo || v > hi) return false;
  return step == 0 || (v - lo) % step == 0;
}

bool size_matches(const SizeOffer& s, uint32_t w, uint32_t h) {
  return fits(w, s.min_width_px, s.max_width_px, s.step_width_px) &&
         fits(h, s.min_height_px, s.max_height_px, s.step_height_px);
}

// Drivers report rates as fractions (e.g. 1/30.000030); 1% tolerance absorbs the rounding.
bool rate_matches(const SizeOffer& s, double rate_hz) {
  if (s.rates_hz.empty()) return true;
  for (double r : s.rates_hz) {
    if (std::abs(r - rate_hz) <= 0.01 * rate_hz) return true;
  }
  return false;
}

std::string rate_text(double r) {
  std::ostringstream o;
  o << r;
  return o.str();
}

std::string size_text(const SizeOffer& s) {
  std::string t;
  if (s.min_width_px == s.max_width_px && s.min_height_px == s.max_height_px) {
    t = std::to_string(s.min_width_px) + "x" + std::to_string(s.min_height_px);
  } else {
    t = std::to_string(s.min_width_px) + "x" + std::to_string(s.min_height_px) + ".." +
        std::to_string(s.max_width_px) + "x" + std::to_string(s.max_height_px);
  }
  for (size_t i = 0; i < s.rates_hz.size(); ++i) {
    t.push_back(i == 0 ? '@' : ',');
    t.append(rate_text(s.rates_hz[i]));
  }
  return t;
}

std::vector<uint32_t> wanted_fourccs(const std::string& pixel_format) {
  if (pixel_format == "yuyv") return {kFourccYuyv};
  if (pixel_format == "mjpeg") return {kFourccMjpeg};
  return {kFourccYuyv, kFourccMjpeg};
}

const FormatOffer* find_format(const std::vector<FormatOffer>& offers, uint32_t code) {
  for (const auto& f : offers) {
    if (f.fourcc == code) return &f;
  }
  return nullptr;
}

}  // namespace

std::string fourcc_text(uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((code >> (8 * i)) & 0xFF);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string describe_offers(const std::vector<FormatOffer>& offers) {
  if (offers.empty()) return "no capture formats";
  std::string out;
  for (size_t i = 0; i < offers.size(); ++i) {
    if (i > 0) out += "; ";
    out += fourcc_text(offers[i].fourcc);
    for (const auto& s : offers[i].sizes) {
      out.push_back(' ');
      out.append(size_text(s));
    }
  }
  return out;
}

Result<FormatChoice> negotiate_format(const std::vector<FormatOffer>& offers,
                                      const FormatRequest& request, const std::string& device) {
  const std::string wanted = std::to_string(request.width_px) + "x" +
                             std::to_string(request.height_px) + "@" + rate_text(request.rate_hz);
  bool any_format = false;
  bool any_size = false;
  for (uint32_t code : wanted_fourccs(request.pixel_format)) {
    const FormatOffer* f = find_format(offers, code);
    if (f == nullptr) continue;
    any_format = true;
    for (const auto& s : f->sizes) {
      if (!size_matches(s, request.width_px, request.height_px)) continue;
      any_size = true;
      if (rate_matches(s, request.rate_hz)) {
        return FormatChoice{code, request.width_px, request.height_px, request.rate_hz};
      }
    }
  }
  std::string what = request.pixel_format == "any"    ? "YUYV or MJPG"
                     : request.pixel_format == "yuyv" ? "YUYV"
                                                      : "MJPG";
  std::string problem = !any_format ? "does not offer " + what
                        : !any_size
                            ? "does not offer " + what + " at " + std::to_string(request.width_px) +
                                  "x" + std::to_string(request.height_px)
                            : "does not offer " + what + " " + wanted;
  return fail(device + " " + problem + "; it offers: " + describe_offers(offers));
}

}  // namespace stereoball::camera_server
