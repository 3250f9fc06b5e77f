// Camera-path interpolation: key frames are hit exactly, in-between samples
// are linear in eye/center/up (and lens), t is clamped, and resampling spreads
// frames evenly over the whole path.
#include <gtest/gtest.h>

#include <stdexcept>

#include "host/suite/CameraPathInterp.hpp"

namespace ml {
namespace {

CameraPath twoKeys() {
  CameraPath p;
  Camera a, b;
  a.eye = {0, 0, 0};
  a.center = {0, 0, -1};
  a.up = {0, 1, 0};
  a.fovy_degrees = 40;
  b.eye = {10, 2, 0};
  b.center = {10, 2, -1};
  b.up = {0, 3, 0};
  b.fovy_degrees = 60;
  b.near_plane = 0.5f;
  p.frames = {a, b};
  return p;
}

TEST(SuiteCameraInterp, KeyFramesAndMidpoints) {
  const CameraPath p = twoKeys();
  EXPECT_EQ(cameraAt(p, 0.0).eye, p.frames[0].eye);
  EXPECT_EQ(cameraAt(p, 1.0).eye, p.frames[1].eye);
  const Camera m = cameraAt(p, 0.25);
  EXPECT_FLOAT_EQ(m.eye.x, 2.5f);
  EXPECT_FLOAT_EQ(m.eye.y, 0.5f);
  EXPECT_FLOAT_EQ(m.center.x, 2.5f);
  EXPECT_FLOAT_EQ(m.up.y, 1.5f);
  EXPECT_FLOAT_EQ(m.fovy_degrees, 45.0f);
  EXPECT_FLOAT_EQ(m.near_plane, 0.1f + (0.5f - 0.1f) * 0.25f);
}

TEST(SuiteCameraInterp, ClampsOutsideThePath) {
  const CameraPath p = twoKeys();
  EXPECT_EQ(cameraAt(p, -3.0).eye, p.frames[0].eye);
  EXPECT_EQ(cameraAt(p, 7.5).eye, p.frames[1].eye);
  CameraPath one;
  one.frames = {p.frames[1]};
  EXPECT_EQ(cameraAt(one, 0.7).eye, p.frames[1].eye);
  EXPECT_THROW(cameraAt(CameraPath{}, 0.0), std::invalid_argument);
}

TEST(SuiteCameraInterp, ResampleSpreadsFramesEvenly) {
  const CameraPath p = twoKeys();
  const CameraPath r = resampleCameraPath(p, 5);
  ASSERT_EQ(r.frames.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(r.frames[i].eye.x, 2.5f * i);
  EXPECT_EQ(r.frames.back().eye, p.frames.back().eye);
  EXPECT_EQ(resampleCameraPath(p, 1).frames.front().eye, p.frames.front().eye);
  EXPECT_THROW(resampleCameraPath(p, 0), std::invalid_argument);

  // Thinning a long path keeps its ends and lands on key frames where they line up.
  CameraPath longp;
  for (int i = 0; i < 9; ++i) {
    Camera c;
    c.eye = {float(i), 0, 0};
    c.center = {float(i), 0, -1};
    longp.frames.push_back(c);
  }
  const CameraPath thin = resampleCameraPath(longp, 3);
  ASSERT_EQ(thin.frames.size(), 3u);
  EXPECT_FLOAT_EQ(thin.frames[1].eye.x, 4.0f);
  EXPECT_FLOAT_EQ(thin.frames[2].eye.x, 8.0f);
}

}  // namespace
}  // namespace ml
