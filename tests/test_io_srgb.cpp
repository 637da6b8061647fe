// sRGB transfer functions (math/color.h) against the IEC 61966-2-1 definition evaluated independently.
#include <gtest/gtest.h>
#include <microshadow/math/color.h>

#include <cmath>

namespace msh {
namespace {

TEST(Srgb, PublishedValuesAndBreakpoints) {
  // Reference values computed in double from the standard's formula by hand (Python, independent of the
  // code).
  EXPECT_NEAR(srgb_to_linear(0.5), 0.21404114048223255, 1e-15);
  EXPECT_NEAR(linear_to_srgb(0.18), 0.46135612950044164, 1e-15);
  EXPECT_NEAR(srgb_to_linear(128.0 / 255.0), 0.21586050011389926, 1e-15);
  EXPECT_NEAR(srgb_to_linear(0.04045), 0.04045 / 12.92, 1e-17);
  EXPECT_NEAR(linear_to_srgb(0.0031308), 0.0031308 * 12.92, 1e-17);
  EXPECT_DOUBLE_EQ(srgb_to_linear(0.0), 0.0);
  EXPECT_NEAR(srgb_to_linear(1.0), 1.0, 1e-15);
  EXPECT_NEAR(linear_to_srgb(1.0), 1.0, 1e-15);
  // The two segments (nearly) meet at the breakpoint: the standard's curve is continuous to ~1e-8.
  const double c = 0.04045;
  EXPECT_NEAR(std::pow((c + 0.055) / 1.055, 2.4), c / 12.92, 1e-7);
  EXPECT_NEAR(srgb_to_linear(std::nextafter(c, 1.0)), srgb_to_linear(c), 1e-7);
}

TEST(Srgb, RoundTripMonotoneFiniteScalarAndRgb) {
  double prev = -1;
  for (int i = 0; i <= 4096; ++i) {
    const double x = i / 4096.0;
    const double l = srgb_to_linear(x);
    EXPECT_GT(l, prev);
    prev = l;
    EXPECT_NEAR(linear_to_srgb(l), x, 1e-12);
    EXPECT_NEAR(double(linear_to_srgb(srgb_to_linear(float(x)))), x, 2e-6);
  }
  const Rgbf c = srgb_to_linear(Rgbf(0.5f, 0.04f, 1.f));
  EXPECT_FLOAT_EQ(c.r, srgb_to_linear(0.5f));
  EXPECT_FLOAT_EQ(c.g, 0.04f / 12.92f);
  EXPECT_NEAR(c.b, 1.f, 1e-6f);
  const Rgbd e = linear_to_srgb(Rgbd(0.0, 0.5, -0.01));
  EXPECT_EQ(e.r, 0.0);
  EXPECT_NEAR(e.b, -0.1292, 1e-15);  // negative input: linear segment, finite
  EXPECT_TRUE(std::isfinite(srgb_to_linear(-0.5)));
}

}  // namespace
}  // namespace msh
