/***************************************************************************
  distortion.h - lens distortion models as templated functions
  -------------------------------------------------------------------------
  Each model is a function of a parameter array, templated on the scalar type
  so that it works with double and with ceres::Jet (automatic derivatives for
  Newton inversion here and for self-calibration in the bundle adjustment).

  Coefficient array layout, for every model (OpenCV's order):
      coeffs[0] = k1, coeffs[1] = k2, coeffs[2] = p1, coeffs[3] = p2, coeffs[4] = k3
 ***************************************************************************/
#ifndef GEOSTATION_CAMERA_DISTORTION_H
#define GEOSTATION_CAMERA_DISTORTION_H

namespace geostation
{

  //! Number of coefficients of every distortion model (k1, k2, p1, p2, k3).
  constexpr int kDistortionCoefficientCount = 5;

  /**
   * OpenCV's forward lens model (exactly cv::projectPoints): maps ideal
   * normalised coordinates (x right, y down, in units of the focal length)
   * to distorted normalised coordinates.
   *
   *   r2 = x^2 + y^2
   *   xd = x (1 + k1 r2 + k2 r2^2 + k3 r2^3) + 2 p1 x y + p2 (r2 + 2 x^2)
   *   yd = y (1 + k1 r2 + k2 r2^2 + k3 r2^3) + p1 (r2 + 2 y^2) + 2 p2 x y
   */
  template <typename T, typename C>
  void opencvDistort( const C *coeffs, const T &x, const T &y, T *xd, T *yd )
  {
    const C &k1 = coeffs[0];
    const C &k2 = coeffs[1];
    const C &p1 = coeffs[2];
    const C &p2 = coeffs[3];
    const C &k3 = coeffs[4];
    const T r2 = x * x + y * y;
    const T radial = T( 1.0 ) + r2 * ( k1 + r2 * ( k2 + r2 * k3 ) );
    *xd = x * radial + T( 2.0 ) * p1 * x * y + p2 * ( r2 + T( 2.0 ) * x * x );
    *yd = y * radial + p1 * ( r2 + T( 2.0 ) * y * y ) + T( 2.0 ) * p2 * x * y;
  }

  /**
   * The photogrammetric correction model (thesis eq. 3.13, Australis/Fraser
   * convention): maps measured photo coordinates (mm, relative to the principal
   * point, x right, y up) to ideal photo coordinates (mm).
   *
   *   r2 = xb^2 + yb^2
   *   xi = xb + xb (k1 r2 + k2 r2^2 + k3 r2^3) + p1 (r2 + 2 xb^2) + 2 p2 xb yb
   *   yi = yb + yb (k1 r2 + k2 r2^2 + k3 r2^3) + 2 p1 xb yb + p2 (r2 + 2 yb^2)
   *
   * Coefficients are in mm units (k1 in mm^-2, k2 in mm^-4, ...).
   */
  template <typename T, typename C>
  void brownPhotoCorrect( const C *coeffs, const T &xb, const T &yb, T *xi, T *yi )
  {
    const C &k1 = coeffs[0];
    const C &k2 = coeffs[1];
    const C &p1 = coeffs[2];
    const C &p2 = coeffs[3];
    const C &k3 = coeffs[4];
    const T r2 = xb * xb + yb * yb;
    const T radial = r2 * ( k1 + r2 * ( k2 + r2 * k3 ) );
    *xi = xb + xb * radial + p1 * ( r2 + T( 2.0 ) * xb * xb ) + T( 2.0 ) * p2 * xb * yb;
    *yi = yb + yb * radial + T( 2.0 ) * p1 * xb * yb + p2 * ( r2 + T( 2.0 ) * yb * yb );
  }

} // namespace geostation

#endif // GEOSTATION_CAMERA_DISTORTION_H
