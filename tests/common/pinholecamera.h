// A pinhole camera (no distortion) with the principal point at the frame's
// centre: the camera most tests and benchmarks start from.
#ifndef GEOSTATION_TESTS_PINHOLECAMERA_H
#define GEOSTATION_TESTS_PINHOLECAMERA_H

#include <string>

#include "camera/camera.h"

namespace geostation
{
  //! `width` x `height` pixels, principal distance `f` in pixels, principal point at the centre.
  inline Camera centredPinhole( const std::string &id, int width, int height, double f )
  {
    Camera c;
    c.id = id;
    c.width = width;
    c.height = height;
    c.f = f;
    c.cx = 0.5 * width;
    c.cy = 0.5 * height;
    return c;
  }
} // namespace geostation

#endif // GEOSTATION_TESTS_PINHOLECAMERA_H
