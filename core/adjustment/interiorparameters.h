/***************************************************************************
  interiorparameters.h - the interior parameter block of the adjustments
  -------------------------------------------------------------------------
  f, cx, cy (pixels) and the lens coefficients k1, k2, p1, p2, k3 (the
  camera model's units) as one array, in this order.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_INTERIORPARAMETERS_H
#define GEOSTATION_ADJUSTMENT_INTERIORPARAMETERS_H

#include <array>
#include <optional>
#include <string>

#include "camera/camera.h"

namespace geostation
{

  //! Indices into the interior parameter block.
  enum InteriorIndex
  {
    kInteriorF = 0,
    kInteriorCx,
    kInteriorCy,
    kInteriorK1,
    kInteriorK2,
    kInteriorP1,
    kInteriorP2,
    kInteriorK3,
    kInteriorSize
  };

  //! Names of the interior parameters: f, cx, cy, k1, k2, p1, p2, k3.
  const std::array<const char *, kInteriorSize> &interiorParameterNames();

  //! Index of an interior parameter name, or nothing.
  std::optional<int> interiorParameterIndex( const std::string &name );

  //! Fills an interior parameter block from a camera.
  inline void interiorBlockFromCamera( const Camera &camera, double *interior )
  {
    interior[kInteriorF] = camera.f;
    interior[kInteriorCx] = camera.cx;
    interior[kInteriorCy] = camera.cy;
    interior[kInteriorK1] = camera.distortion.k1();
    interior[kInteriorK2] = camera.distortion.k2();
    interior[kInteriorP1] = camera.distortion.p1();
    interior[kInteriorP2] = camera.distortion.p2();
    interior[kInteriorK3] = camera.distortion.k3();
  }

  //! Writes an interior parameter block back into a camera.
  inline void cameraFromInteriorBlock( const double *interior, Camera *camera )
  {
    camera->f = interior[kInteriorF];
    camera->cx = interior[kInteriorCx];
    camera->cy = interior[kInteriorCy];
    camera->distortion.coeffs = { interior[kInteriorK1], interior[kInteriorK2], interior[kInteriorP1], interior[kInteriorP2], interior[kInteriorK3] };
  }

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_INTERIORPARAMETERS_H
