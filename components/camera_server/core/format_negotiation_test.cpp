#include "camera_server/core/format_negotiation.hpp"

#include <gtest/gtest.h>

namespace stereoball::camera_server {
namespace {

SizeOffer discrete(uint32_t w, uint32_t h, std::vector<double> rates) {
  SizeOffer s;
  s.min_width_px = s.max_width_px = w;
  s.min_height_px = s.max_height_px = h;
  s.rates_hz = std::move(rates);
  return s;
}

// A typical UVC webcam: YUYV only at low sizes/rates, MJPEG everywhere.
std::vector<FormatOffer> webcam() {
  return {{kFourccYuyv, "YUYV 4:2:2", {discrete(640, 480, {30, 15}), discrete(1280, 720, {10})}},
          {kFourccMjpeg, "Motion-JPEG", {discrete(640, 480, {30}), discrete(1280, 720, {30})}}};
}

TEST(NegotiateFormat, GivenAnyAndYuyvOfferedWhenNegotiatedThenYuyvPreferred) {
  auto r = negotiate_format(webcam(), {"any", 640, 480, 30.0}, "/dev/video0");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->fourcc, kFourccYuyv);
  EXPECT_EQ(r->width_px, 640u);
  EXPECT_DOUBLE_EQ(r->rate_hz, 30.0);
}

TEST(NegotiateFormat, GivenAnyAndYuyvTooSlowAtSizeWhenNegotiatedThenFallsBackToMjpeg) {
  auto r = negotiate_format(webcam(), {"any", 1280, 720, 30.0}, "/dev/video0");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->fourcc, kFourccMjpeg);
}

TEST(NegotiateFormat, GivenDriverRateWithRoundingWhenNegotiatedThenAccepted) {
  std::vector<FormatOffer> offers{{kFourccYuyv, "", {discrete(640, 480, {29.97})}}};
  EXPECT_TRUE(negotiate_format(offers, {"yuyv", 640, 480, 30.0}, "/dev/video0").ok());
}

TEST(NegotiateFormat, GivenUnsupportedSizeWhenNegotiatedThenErrorListsOffers) {
  auto r = negotiate_format(webcam(), {"yuyv", 800, 600, 30.0}, "/dev/video2");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("/dev/video2"), std::string::npos);
  EXPECT_NE(r.error().find("800x600"), std::string::npos);
  EXPECT_NE(r.error().find("YUYV 640x480@30,15 1280x720@10"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("MJPG 640x480@30"), std::string::npos) << r.error();
}

TEST(NegotiateFormat, GivenUnsupportedRateWhenNegotiatedThenErrorNamesRate) {
  auto r = negotiate_format(webcam(), {"yuyv", 1280, 720, 30.0}, "/dev/video0");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("1280x720@30"), std::string::npos) << r.error();
}

TEST(NegotiateFormat, GivenFormatNotOfferedWhenNegotiatedThenErrorSaysSo) {
  std::vector<FormatOffer> offers{
      {fourcc('G', 'R', 'E', 'Y'), "Greyscale", {discrete(640, 480, {30})}}};
  auto r = negotiate_format(offers, {"mjpeg", 640, 480, 30.0}, "/dev/video0");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("does not offer MJPG"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("GREY 640x480@30"), std::string::npos) << r.error();
}

TEST(NegotiateFormat, GivenStepwiseSizesWhenNegotiatedThenSizesOnTheGridAccepted) {
  SizeOffer s;
  s.min_width_px = 160;
  s.max_width_px = 1920;
  s.step_width_px = 16;
  s.min_height_px = 120;
  s.max_height_px = 1080;
  s.step_height_px = 8;
  std::vector<FormatOffer> offers{{kFourccYuyv, "", {s}}};
  EXPECT_TRUE(negotiate_format(offers, {"yuyv", 640, 480, 30.0}, "d").ok());
  EXPECT_FALSE(negotiate_format(offers, {"yuyv", 650, 480, 30.0}, "d").ok());
}

TEST(NegotiateFormat, GivenNoFormatsWhenNegotiatedThenErrorSaysNoCaptureFormats) {
  auto r = negotiate_format({}, {"any", 640, 480, 30.0}, "/dev/video9");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("no capture formats"), std::string::npos);
}

TEST(FourccText, GivenCodesWhenPrintedThenFourCharacters) {
  EXPECT_EQ(fourcc_text(kFourccYuyv), "YUYV");
  EXPECT_EQ(fourcc_text(kFourccMjpeg), "MJPG");
}

}  // namespace
}  // namespace stereoball::camera_server
