/***************************************************************************
  filmscan.cpp - fiducials, scan affine and rendered marks of scanned film
 ***************************************************************************/
#include "simulation/filmscan.h"

#include <cmath>

#include "geometry/rotation.h"

namespace geostation
{

  std::vector<Fiducial> filmFiducials( const Camera &camera )
  {
    const double ps = camera.pixelSizeMm.value_or( 0.1 );
    const double halfW = 0.5 * camera.width * ps, halfH = 0.5 * camera.height * ps / camera.aspect;
    // mark centres two diameters inside the frame, where a detector's template fits around them
    const double mx = halfW - 2.0 * kFiducialDiameterPx * ps, my = halfH - 2.0 * kFiducialDiameterPx * ps;
    return { { "F1", { -mx, my } }, { "F2", { mx, my } }, { "F3", { mx, -my } }, { "F4", { -mx, -my } },
      { "F5", { 0.0, my } }, { "F6", { mx, 0.0 } }, { "F7", { 0.0, -my } }, { "F8", { -mx, 0.0 } } };
  }

  Eigen::Matrix<double, 2, 3> simulatedScan( const Camera &camera, std::mt19937 &random )
  {
    std::uniform_real_distribution<double> u( 0.0, 1.0 );
    const double ps = *camera.pixelSizeMm;
    const double beta = degToRad( ( 0.1 + 0.3 * u( random ) ) * ( u( random ) < 0.5 ? -1 : 1 ) );
    const double affinity = 0.0005 + 0.001 * u( random );
    const Eigen::Vector2d shift( 0.2 * ( 2 * u( random ) - 1 ), 0.2 * ( 2 * u( random ) - 1 ) );
    Eigen::Matrix<double, 2, 3> nominal; // photo mm of a pixel on the camera's nominal grid
    nominal << ps, 0.0, -camera.cx * ps, 0.0, -ps / camera.aspect, camera.cy * ps / camera.aspect;
    Eigen::Matrix2d rotation;
    rotation << std::cos( beta ), -std::sin( beta ), std::sin( beta ), std::cos( beta );
    const Eigen::Matrix2d scale = Eigen::Vector2d( 1.0 + 0.5 * affinity, 1.0 - 0.5 * affinity ).asDiagonal();
    Eigen::Matrix<double, 2, 3> scan;
    scan.leftCols<2>() = rotation * scale * nominal.leftCols<2>();
    scan.col( 2 ) = rotation * scale * nominal.col( 2 ) + shift;
    return scan;
  }

  Eigen::Vector2d fiducialNominalPixel( const Camera &camera, const Fiducial &fiducial )
  {
    const double ps = *camera.pixelSizeMm;
    return Eigen::Vector2d( camera.cx + fiducial.photoMm.x() / ps, camera.cy - fiducial.photoMm.y() * camera.aspect / ps );
  }

  void drawFiducialMarks( cv::Mat &linearRgb, const Camera &camera, const OrientedImage &scan )
  {
    // a bright disc on a dark square 3 diameters wide, as marks sit on the dark film border
    const double radius = 0.5 * kFiducialDiameterPx, border = kFiducialSquareHalfPx;
    constexpr int kSamples = 8;
    for ( const Fiducial &f : camera.fiducials )
    {
      const Eigen::Vector2d centre = scan.scanFromNominal( fiducialNominalPixel( camera, f ) );
      const int c0 = std::max( 0, static_cast<int>( std::floor( centre.x() - border - 1 ) ) ), c1 = std::min( linearRgb.cols - 1, static_cast<int>( std::ceil( centre.x() + border + 1 ) ) );
      const int r0 = std::max( 0, static_cast<int>( std::floor( centre.y() - border - 1 ) ) ), r1 = std::min( linearRgb.rows - 1, static_cast<int>( std::ceil( centre.y() + border + 1 ) ) );
      for ( int r = r0; r <= r1; ++r )
        for ( int c = c0; c <= c1; ++c )
        {
          int inDisc = 0, inBorder = 0;
          for ( int sj = 0; sj < kSamples; ++sj )
            for ( int si = 0; si < kSamples; ++si )
            {
              const Eigen::Vector2d offset = Eigen::Vector2d( c + ( si + 0.5 ) / kSamples, r + ( sj + 0.5 ) / kSamples ) - centre;
              inDisc += offset.norm() <= radius ? 1 : 0;
              inBorder += offset.cwiseAbs().maxCoeff() <= border ? 1 : 0;
            }
          const float disc = static_cast<float>( inDisc ) / ( kSamples * kSamples ), dark = static_cast<float>( inBorder - inDisc ) / ( kSamples * kSamples );
          cv::Vec3f &p = linearRgb.at<cv::Vec3f>( r, c );
          p = p * ( 1.0f - disc - dark ) + cv::Vec3f( 0.95f, 0.95f, 0.95f ) * disc + cv::Vec3f( 0.03f, 0.03f, 0.03f ) * dark;
        }
    }
  }

} // namespace geostation
