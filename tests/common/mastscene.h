/***************************************************************************
  mastscene.h - a photo from a mast over signalised control, rendered
  independently of the survey simulator
  -------------------------------------------------------------------------
  A second scene generator with conventions of its own: OpenCV's camera
  (x right, y down, z forward; pixel centres at integers; K and R, t as
  cv::projectPoints takes them), a flat field in metres with a north-east
  frame, shaded by its own procedural texture, and targets drawn by ray
  casting with 4 x 4 samples a pixel: a white disc in a dark ring on the
  grass. The camera stands on a 12 m mast and looks down the field, so the
  targets range from about 60 px across near the mast to 19 px far off,
  flattened by the view into ellipses, and two smaller ones among the far
  ones are 15 and 8 px across (3 px high). Decoys: white discs without a ring,
  white squares and bright patches of the same sizes. Only the result is
  turned into GeoStation's conventions (camera, exterior orientation,
  control points, the true pixels of the disc centres).
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_MASTSCENE_H
#define GEOSTATION_TESTS_MASTSCENE_H

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "adjustment/controlpoint.h"
#include "camera/camera.h"
#include "geometry/exteriororientation.h"

namespace geostation::mastscene
{
  struct Target
  {
    std::string id;
    Eigen::Vector2d groundNE;  //!< north, east (m)
    double radiusM = 0.0;      //!< of the white disc; the dark ring reaches 1.8 times as far
    bool decoy = false;        //!< no control point: a disc without ring, a square or a patch
    int decoyKind = 0;
  };

  struct MastScene
  {
    cv::Mat grey;                                     //!< 8-bit
    Camera camera;                                    //!< GeoStation's, lens model none
    ExteriorOrientation truth;                        //!< GeoStation's
    std::vector<ControlPoint> control;                //!< block CRS: x east, y north, z up
    std::map<std::string, Eigen::Vector2d> truePixel; //!< the disc centres' true pixels, GeoStation's convention
    std::map<std::string, double> acrossPx;           //!< each target's disc across in the image (its widest)
    std::map<std::string, bool> wholeInFrame;         //!< the ring wholly inside the frame
  };

  //! The scene: 16 targets from 6 to 38 m along the field, 10 decoys, a mast 12 m high (seed: texture, noise, layout jitter).
  inline MastScene mastScene( uint32_t seed = 1 )
  {
    std::mt19937 random( seed );
    std::uniform_real_distribution<double> jitter( -0.8, 0.8 );
    std::normal_distribution<double> noise( 0.0, 2.0 );
    const int width = 1280, height = 960;
    const double f = 1000.0, u0 = 639.5 + 3.0, v0 = 479.5 - 2.0; // OpenCV: centres at integers
    // OpenCV camera: at (N 0, E 0, up 12), looking north, 38 degrees down
    const double down = 38.0 * M_PI / 180.0, mastM = 12.0;
    // world axes (east, north, up); camera axes: x right (east), y down, z forward
    const Eigen::Vector3d forward( 0.0, std::cos( down ), -std::sin( down ) ), right( 1.0, 0.0, 0.0 );
    const Eigen::Vector3d downAxis = forward.cross( right );
    Eigen::Matrix3d cameraFromWorld;
    cameraFromWorld.row( 0 ) = right.transpose();
    cameraFromWorld.row( 1 ) = downAxis.transpose();
    cameraFromWorld.row( 2 ) = forward.transpose();
    const Eigen::Vector3d centre( 0.0, 0.0, mastM );

    std::vector<Target> targets;
    const double along[] = { 6.5, 8.0, 9.5, 11.0, 13.0, 15.0, 17.5, 20.0, 23.0, 26.0, 29.0, 32.0, 35.0, 38.0 };
    for ( int k = 0; k < 14; ++k )
    {
      const double n = along[k] + 0.5 * jitter( random );
      const double halfWidth = 0.8 * ( n * std::cos( down ) + mastM * std::sin( down ) ) * ( 0.5 * width / f );
      const double e = ( k % 2 ? 1.0 : -1.0 ) * ( 0.15 + 0.6 * std::abs( jitter( random ) ) ) * halfWidth;
      targets.push_back( { "T" + std::to_string( 100 + k ), { n, e }, 0.35, false, 0 } );
    }
    // two small targets among the far ones (0.4 and 0.28 m discs): 15 and 8 px across, 3 px high
    for ( int k = 0; k < 2; ++k )
    {
      const double n = 24.0 + 12.0 * k + 0.5 * jitter( random );
      const double halfWidth = 0.8 * ( n * std::cos( down ) + mastM * std::sin( down ) ) * ( 0.5 * width / f );
      targets.push_back( { "S" + std::to_string( 200 + k ), { n, ( k % 2 ? -0.35 : 0.4 ) * halfWidth }, k ? 0.14 : 0.2, false, 0 } );
    }
    for ( int k = 0; k < 10; ++k )
    {
      const double n = 7.0 + 28.0 * ( k + 0.5 ) / 10.0 + jitter( random );
      const double halfWidth = 0.8 * ( n * std::cos( down ) + mastM * std::sin( down ) ) * ( 0.5 * width / f );
      const double e = ( k % 2 ? -1.0 : 1.0 ) * ( 0.1 + 0.7 * std::abs( jitter( random ) ) ) * halfWidth;
      targets.push_back( { "D" + std::to_string( k ), { n, e }, 0.25 + 0.15 * ( k % 3 ), true, k % 3 } );
    }

    // the field's grey: grass-like texture, darker and lighter strips (mowing), all in ground metres
    const double phase1 = jitter( random ) * 3, phase2 = jitter( random ) * 3;
    const auto field = [&]( double n, double e )
    {
      const double strips = 8.0 * std::sin( 0.9 * e + phase1 );
      const double fine = 6.0 * std::sin( 7.3 * n + 3.1 * e + phase2 ) * std::sin( 5.7 * e - 2.3 * n );
      return 105.0 + strips + fine;
    };
    const auto shade = [&]( double n, double e )
    {
      for ( const Target &t : targets )
      {
        const double dn = n - t.groundNE.x(), de = e - t.groundNE.y(), r = std::hypot( dn, de );
        if ( !t.decoy )
        {
          if ( r <= t.radiusM )
            return 235.0;
          if ( r <= 1.8 * t.radiusM )
            return 25.0;
        }
        else if ( t.decoyKind == 0 && r <= t.radiusM )
          return 225.0; // a white disc on the grass: no ring
        else if ( t.decoyKind == 1 && std::abs( dn ) <= t.radiusM && std::abs( de ) <= t.radiusM )
          return 230.0; // a white square
        else if ( t.decoyKind == 2 && r <= 1.8 * t.radiusM )
          return 170.0 + 40.0 * std::cos( 3.0 * std::atan2( dn, de ) ); // a bright patch with an uneven edge
      }
      return field( n, e );
    };

    cv::Mat grey( height, width, CV_8U );
    const Eigen::Matrix3d worldFromCamera = cameraFromWorld.transpose();
    constexpr int kSamples = 4;
    for ( int v = 0; v < height; ++v )
      for ( int u = 0; u < width; ++u )
      {
        double sum = 0.0;
        int hits = 0;
        for ( int sv = 0; sv < kSamples; ++sv )
          for ( int su = 0; su < kSamples; ++su )
          {
            const double x = ( u - 0.5 + ( su + 0.5 ) / kSamples - u0 ) / f, y = ( v - 0.5 + ( sv + 0.5 ) / kSamples - v0 ) / f;
            const Eigen::Vector3d d = worldFromCamera * Eigen::Vector3d( x, y, 1.0 );
            if ( d.z() >= -1e-6 )
            {
              sum += 200.0; // sky
              ++hits;
              continue;
            }
            const double s = -centre.z() / d.z();
            const Eigen::Vector3d g = centre + s * d;
            sum += shade( g.y(), g.x() );
            ++hits;
          }
        grey.at<uint8_t>( v, u ) = cv::saturate_cast<uint8_t>( sum / hits + noise( random ) );
      }
    cv::GaussianBlur( grey, grey, cv::Size( 0, 0 ), 0.5 );

    MastScene scene;
    scene.grey = grey;
    scene.camera.id = "mast";
    scene.camera.width = width;
    scene.camera.height = height;
    scene.camera.f = f;
    scene.camera.aspect = 1.0;
    scene.camera.cx = u0 + 0.5; // GeoStation's pixel centres are at i + 0.5
    scene.camera.cy = v0 + 0.5;
    scene.camera.pixelSizeMm = 0.005;
    // GeoStation's camera frame: x right, y up, z back
    Eigen::Matrix3d worldFromOurs;
    worldFromOurs.col( 0 ) = right;
    worldFromOurs.col( 1 ) = -downAxis;
    worldFromOurs.col( 2 ) = -forward;
    scene.truth = ExteriorOrientation::fromCentreAndRotation( centre, worldFromOurs );
    for ( const Target &t : targets )
    {
      if ( t.decoy )
        continue;
      ControlPoint c;
      c.id = t.id;
      c.world = Eigen::Vector3d( t.groundNE.y(), t.groundNE.x(), 0.0 );
      scene.control.push_back( c );
      const Eigen::Vector3d p = cameraFromWorld * ( c.world - centre );
      scene.truePixel[t.id] = Eigen::Vector2d( u0 + f * p.x() / p.z() + 0.5, v0 + f * p.y() / p.z() + 0.5 );
      double widest = 0.0;
      for ( int a = 0; a < 4; ++a )
      {
        const double angle = a * M_PI / 4.0;
        const Eigen::Vector3d w = c.world + t.radiusM * Eigen::Vector3d( std::cos( angle ), std::sin( angle ), 0.0 );
        const Eigen::Vector3d q = cameraFromWorld * ( w - centre ), o = cameraFromWorld * ( c.world - t.radiusM * Eigen::Vector3d( std::cos( angle ), std::sin( angle ), 0.0 ) - centre );
        widest = std::max( widest, std::hypot( f * ( q.x() / q.z() - o.x() / o.z() ), f * ( q.y() / q.z() - o.y() / o.z() ) ) );
      }
      scene.acrossPx[t.id] = widest;
      bool inside = true;
      for ( int a = 0; a < 36; ++a )
      {
        const Eigen::Vector3d w = c.world + 1.8 * t.radiusM * Eigen::Vector3d( std::cos( a * M_PI / 18.0 ), std::sin( a * M_PI / 18.0 ), 0.0 );
        const Eigen::Vector3d q = cameraFromWorld * ( w - centre );
        const double u = u0 + f * q.x() / q.z(), v = v0 + f * q.y() / q.z();
        inside = inside && u >= 0.0 && v >= 0.0 && u <= width - 1.0 && v <= height - 1.0;
      }
      scene.wholeInFrame[t.id] = inside;
    }
    return scene;
  }

} // namespace geostation::mastscene

#endif // GEOSTATION_TESTS_MASTSCENE_H
