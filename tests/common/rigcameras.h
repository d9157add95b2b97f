/***************************************************************************
  rigcameras.h - a small rig camera for the import tests and fuzz targets
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_RIGCAMERAS_H
#define GEOSTATION_TESTS_RIGCAMERAS_H

#include <string>

#include "io/opencvcalibration.h"

namespace geostation::testing
{
  //! A 64 x 48 camera "front" (f 50 px, principal point at the centre), no lever arm, boresight or pattern.
  inline RigCamera forwardRigCamera( const std::string &imagePattern = std::string() )
  {
    RigCamera c;
    c.camera.id = "front";
    c.camera.width = 64;
    c.camera.height = 48;
    c.camera.f = 50;
    c.camera.cx = 32;
    c.camera.cy = 24;
    c.imagePattern = imagePattern;
    return c;
  }
} // namespace geostation::testing

#endif // GEOSTATION_TESTS_RIGCAMERAS_H
