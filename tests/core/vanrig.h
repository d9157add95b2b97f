// Test fixture: oriented images of a survey van (two stations, three
// cameras each, one per lens model), looking north along a road at Z = 100.
#ifndef GEOSTATION_TESTS_VANRIG_H
#define GEOSTATION_TESTS_VANRIG_H

#include <memory>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/projection.h"
#include "geometry/rotation.h"

namespace vanrig
{
  using namespace geostation;

  inline ExteriorOrientation lookAt( const Eigen::Vector3d &centre, const Eigen::Vector3d &target )
  {
    const Eigen::Vector3d forward = ( target - centre ).normalized();
    const Eigen::Vector3d right = forward.cross( Eigen::Vector3d::UnitZ() ).normalized();
    const Eigen::Vector3d up = right.cross( forward );
    Eigen::Matrix3d worldFromCamera;
    worldFromCamera << right, up, -forward;
    return ExteriorOrientation::fromCentreAndRotation( centre, worldFromCamera );
  }

  inline Camera camera( DistortionModel model )
  {
    Camera c;
    c.id = distortionModelName( model );
    c.width = 1280;
    c.height = 960;
    c.f = 1100.0;
    c.cx = 641.3;
    c.cy = 478.9;
    c.pixelSizeMm = 0.0074;
    c.distortion.model = model;
    if ( model == DistortionModel::OpenCV )
      c.distortion.coeffs = { -0.2, 0.05, 0.0005, -0.0003, 0.0 };
    if ( model == DistortionModel::BrownPhoto )
      c.distortion.coeffs = { 2e-3, -1e-5, 1e-5, -2e-5, 0.0 };
    return c;
  }

  //! Six images: stations at Y = 0 and Y = 5 m, cameras 1 m left, centre, 1 m right, 2.5 m above the road.
  inline std::vector<std::unique_ptr<OrientedImage>> images()
  {
    std::vector<std::unique_ptr<OrientedImage>> out;
    const DistortionModel models[3] = { DistortionModel::OpenCV, DistortionModel::None, DistortionModel::BrownPhoto };
    for ( double y : { 0.0, 5.0 } )
      for ( int k = 0; k < 3; ++k )
      {
        const Eigen::Vector3d centre( 500000.0 + ( k - 1 ) * 1.0, 4400000.0 + y, 102.5 );
        const Eigen::Vector3d target = centre + Eigen::Vector3d( ( k - 1 ) * 4.0, 30.0, -2.0 );
        out.push_back( std::make_unique<OrientedImage>( camera( models[k] ), lookAt( centre, target ) ) );
      }
    return out;
  }

  //! A point 15-30 m ahead of the first station, seen by all six images.
  inline Eigen::Vector3d pointAhead( std::mt19937 &rng )
  {
    std::uniform_real_distribution<double> x( -3.0, 3.0 ), y( 15.0, 30.0 ), z( 100.0, 104.0 );
    return { 500000.0 + x( rng ), 4400000.0 + y( rng ), z( rng ) };
  }
}

#endif
