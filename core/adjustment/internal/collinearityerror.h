/***************************************************************************
  collinearityerror.h - the collinearity equations as a Ceres cost functor
  -------------------------------------------------------------------------
  Residual of one image observation, whitened by its pixel sigma, as a
  function of three parameter blocks:

    pose[6]     = X0, Y0, Z0 (metres, relative to a local origin),
                  omega, phi, kappa (radians)
    interior[8] = f, cx, cy (pixels), k1, k2, p1, p2, k3 (the model's units)
    point[3]    = X, Y, Z (metres, relative to the same local origin)

  Coordinates are taken relative to a local origin (e.g. the centroid of the
  control) so that UTM-sized numbers do not cost precision in derivatives.

  none / opencv: residual = (projected pixel - observed pixel) / sigma.
  brown_photo:   thesis eq. 3.13 - the observed photo coordinates corrected
                 for distortion minus the collinearity photo coordinates,
                 converted to pixels (x: / ps, y: * aspect / ps) / sigma.
                 To first order this equals the pixel residual.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_COLLINEARITYERROR_H
#define GEOSTATION_ADJUSTMENT_COLLINEARITYERROR_H

#include <ceres/autodiff_cost_function.h>

#include "adjustment/interiorparameters.h"
#include "camera/camera.h"
#include "geometry/rotation.h"

namespace geostation
{

  struct CollinearityError
  {
    CollinearityError( DistortionModel model, double aspect, double pixelSizeMm, double observedCol, double observedRow, double sigmaPx )
      : mModel( model ), mAspect( aspect ), mPixelSizeMm( pixelSizeMm ), mCol( observedCol ), mRow( observedRow ), mWeight( 1.0 / sigmaPx ) {}

    template <typename T>
    bool operator()( const T *pose, const T *interior, const T *point, T *residuals ) const
    {
      T R[9];
      worldFromCameraRotation( pose[3], pose[4], pose[5], R );
      const T d[3] = { point[0] - pose[0], point[1] - pose[1], point[2] - pose[2] };
      // p = R^T d
      const T px = R[0] * d[0] + R[3] * d[1] + R[6] * d[2];
      const T py = R[1] * d[0] + R[4] * d[1] + R[7] * d[2];
      const T pz = R[2] * d[0] + R[5] * d[1] + R[8] * d[2];
      const T xn = -px / pz;
      const T yn = -py / pz;
      const T &f = interior[kInteriorF];
      const T &cx = interior[kInteriorCx];
      const T &cy = interior[kInteriorCy];
      const T coeffs[5] = { interior[kInteriorK1], interior[kInteriorK2], interior[kInteriorP1], interior[kInteriorP2], interior[kInteriorK3] };
      switch ( mModel )
      {
        case DistortionModel::None:
          residuals[0] = ( cx + f * xn - mCol ) * mWeight;
          residuals[1] = ( cy - f * mAspect * yn - mRow ) * mWeight;
          return true;
        case DistortionModel::OpenCV:
        {
          T xd, yd;
          opencvDistort( coeffs, xn, T( -yn ), &xd, &yd );
          residuals[0] = ( cx + f * xd - mCol ) * mWeight;
          residuals[1] = ( cy + f * mAspect * yd - mRow ) * mWeight;
          return true;
        }
        case DistortionModel::BrownPhoto:
        {
          const T xb = ( T( mCol ) - cx ) * mPixelSizeMm;
          const T yb = -( T( mRow ) - cy ) * ( mPixelSizeMm / mAspect );
          T xi, yi;
          brownPhotoCorrect( coeffs, xb, yb, &xi, &yi );
          const T c = f * mPixelSizeMm;
          residuals[0] = ( c * xn - xi ) * ( mWeight / mPixelSizeMm );
          residuals[1] = -( c * yn - yi ) * ( mWeight * mAspect / mPixelSizeMm );
          return true;
        }
      }
      return false;
    }

    //! Ceres 2.1: AutoDiffCostFunction<F, residuals, blocks...>.
    static ceres::CostFunction *create( const Camera &camera, double observedCol, double observedRow, double sigmaPx )
    {
      return new ceres::AutoDiffCostFunction<CollinearityError, 2, 6, kInteriorSize, 3>(
               new CollinearityError( camera.distortion.model, camera.aspect, camera.pixelSizeMm.value_or( 1.0 ), observedCol, observedRow, sigmaPx ) );
    }

    DistortionModel mModel;
    double mAspect;
    double mPixelSizeMm;
    double mCol, mRow;
    double mWeight;
  };

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_COLLINEARITYERROR_H
