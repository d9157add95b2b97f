/***************************************************************************
  rotation.h - omega-phi-kappa rotations (docs/conventions.md §3)
  -------------------------------------------------------------------------
  R = Rx(omega) * Ry(phi) * Rz(kappa) maps camera-frame vectors to object
  space (worldFromCamera). Templated on the scalar so that the adjustment can
  differentiate through it with ceres::Jet.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_ROTATION_H
#define GEOSTATION_GEOMETRY_ROTATION_H

#include <cmath>

#include <Eigen/Core>

namespace geostation
{

  constexpr double kPi = 3.14159265358979323846;
  inline double degToRad( double deg ) { return deg * kPi / 180.0; }
  inline double radToDeg( double rad ) { return rad * 180.0 / kPi; }

  /**
   * worldFromCamera rotation, row-major into R[9], from angles in radians:
   *   R = Rx(omega) * Ry(phi) * Rz(kappa)
   */
  template <typename T>
  void worldFromCameraRotation( const T &omega, const T &phi, const T &kappa, T *R )
  {
    using std::cos;
    using std::sin;
    const T cw = cos( omega ), sw = sin( omega );
    const T cp = cos( phi ), sp = sin( phi );
    const T ck = cos( kappa ), sk = sin( kappa );
    R[0] = cp * ck;
    R[1] = -cp * sk;
    R[2] = sp;
    R[3] = sw * sp * ck + cw * sk;
    R[4] = -sw * sp * sk + cw * ck;
    R[5] = -sw * cp;
    R[6] = -cw * sp * ck + sw * sk;
    R[7] = cw * sp * sk + sw * ck;
    R[8] = cw * cp;
  }

  //! worldFromCamera rotation from omega, phi, kappa in degrees.
  Eigen::Matrix3d worldFromCameraRotationDeg( double omegaDeg, double phiDeg, double kappaDeg );

  /**
   * Omega, phi, kappa (degrees) of a worldFromCamera rotation; phi in
   * [-90, 90], omega and kappa in (-180, 180]. At phi = +-90 (gimbal lock)
   * omega is set to 0 and kappa absorbs the remaining rotation.
   */
  Eigen::Vector3d omegaPhiKappaDegFromRotation( const Eigen::Matrix3d &worldFromCamera );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_ROTATION_H
