/***************************************************************************
  paintedroads.h - road scenes painted independently of the survey simulator
  -------------------------------------------------------------------------
  A vertical aerial pair (one camera model for both photos, 60 % forward
  overlap) over level ground at 300 m, at any ground pixel size. The
  ground is a patchwork of fields, each of its own brightness - some
  brighter than the roads, some darker - with a texture of its own (rows
  or speckle). Three roads cross it, defined in metres:
  - a straight main road of asphalt (grey 105) with a light dashed centre
    marking and light edge lines where the ground pixel resolves them;
  - a winding road of concrete (grey 150);
  - a straight road of dark asphalt (grey 80) with a row of trees along
    one side, some of whose crowns reach over the road.
  Each pixel is the ground's grey where its ray meets it, averaged over
  2 x 2 rays (so a road narrower than a pixel is mixed with its fields),
  then blurred (sigma 0.6 px) and given noise of 2 grey levels.

  Conventions (unlike the simulator's): ground x east, y north, metres
  from the first photo's nadir; the roads' truth is their centre lines on
  the ground, carried into the photos by the collinearity equations.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_PAINTEDROADS_H
#define GEOSTATION_TESTS_PAINTEDROADS_H

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"
#include "imagelinescoring.h"
#include "paintedpair.h"

namespace geostation::paintedroads
{
  struct RoadScene
  {
    std::string name;
    double gsdM = 0.5;          //!< ground pixel
    std::vector<double> widthsM; //!< main, winding, dark road
    int width = 1200;            //!< photo size (height 3/4 of it)
  };

  struct PaintedRoad
  {
    std::string name;
    double widthM = 0.0;
    std::vector<Eigen::Vector2d> centre; //!< ground (x, y), metres
  };

  struct PaintedRoadPair
  {
    Camera camera;
    std::vector<ExteriorOrientation> exterior; //!< A, B
    std::vector<cv::Mat> grey;                 //!< A, B
    std::vector<PaintedRoad> roads;
    double groundM = 300.0;
    double gsdM = 0.5;
  };

  //! The four scenes: low aerial, aerial, regional and satellite ground pixels.
  inline std::vector<RoadScene> scenes()
  {
    return { { "low aerial 0.15 m", 0.15, { 11.0, 8.0, 6.0 } },
             { "aerial 0.5 m", 0.5, { 11.0, 8.0, 6.0 } },
             { "regional 2 m", 2.0, { 14.0, 10.0, 8.0 } },
             { "satellite 10 m", 10.0, { 30.0, 20.0, 12.0 } } };
  }

  //! Distance from p to a polyline.
  inline double distanceTo( const std::vector<Eigen::Vector2d> &line, const Eigen::Vector2d &p )
  {
    double best = 1e300;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
      best = std::min( best, distanceToSegment( p, line[i], line[i + 1] ) );
    return best;
  }

  //! The roads over a footprint of `extentX` x `extentY` metres starting at (x0, y0).
  inline std::vector<PaintedRoad> roadsOver( double x0, double y0, double extentX, double extentY, const std::vector<double> &widthsM )
  {
    std::vector<PaintedRoad> roads( 3 );
    roads[0] = { "main", widthsM[0], { { x0 - 0.1 * extentX, y0 + 0.25 * extentY }, { x0 + 1.1 * extentX, y0 + 0.62 * extentY } } };
    roads[1] = { "winding", widthsM[1], {} };
    for ( int k = 0; k <= 60; ++k )
    {
      const double t = k / 60.0;
      roads[1].centre.emplace_back( x0 - 0.1 * extentX + 1.2 * extentX * t, y0 + 0.8 * extentY + 0.08 * extentY * std::sin( 2.0 * M_PI * 1.3 * t ) );
    }
    roads[2] = { "dark", widthsM[2], { { x0 + 0.55 * extentX, y0 - 0.1 * extentY }, { x0 + 0.62 * extentX, y0 + 1.1 * extentY } } };
    return roads;
  }

  //! The ground's grey at (x, y).
  inline double groundGrey( const std::vector<PaintedRoad> &roads, double fieldM, double x, double y )
  {
    // trees along the dark road, crowns of 0.6 of its width reaching over its edge every few crowns
    const PaintedRoad &dark = roads[2];
    const Eigen::Vector2d p( x, y );
    const double crown = 0.6 * dark.widthM;
    const Eigen::Vector2d a = dark.centre[0], b = dark.centre[1];
    const Eigen::Vector2d along = ( b - a ).normalized(), across( -along.y(), along.x() );
    const double s = ( p - a ).dot( along ), t = ( p - a ).dot( across );
    const long k = static_cast<long>( std::floor( s / ( 2.5 * crown ) ) );
    const double overhang = paintedpair::hashUnit( k, 7, 11 ) < 0.3 ? 0.55 * dark.widthM : 0.5 * dark.widthM + 0.6 * crown;
    const Eigen::Vector2d treeCentre( ( k + 0.5 ) * 2.5 * crown, overhang );
    if ( ( Eigen::Vector2d( s, t ) - treeCentre ).norm() < crown )
      return 45.0 + 10.0 * paintedpair::hashUnit( static_cast<long>( std::floor( s / 0.7 ) ), static_cast<long>( std::floor( t / 0.7 ) ), 12 );
    for ( size_t r = 0; r < roads.size(); ++r )
    {
      const double d = distanceTo( roads[r].centre, p );
      if ( d > 0.5 * roads[r].widthM )
        continue;
      if ( r == 0 )
      {
        const double along0 = ( p - roads[0].centre[0] ).dot( ( roads[0].centre[1] - roads[0].centre[0] ).normalized() );
        if ( d < 0.075 && std::fmod( along0, 9.0 ) < 4.5 )
          return 215.0; // dashed centre marking, 0.15 m
        if ( d > 0.5 * roads[0].widthM - 0.35 && d < 0.5 * roads[0].widthM - 0.2 )
          return 200.0; // edge lines
        return 105.0 + 4.0 * ( paintedpair::hashUnit( static_cast<long>( std::floor( x / 0.4 ) ), static_cast<long>( std::floor( y / 0.4 ) ), 13 ) - 0.5 );
      }
      return r == 1 ? 150.0 : 80.0;
    }
    // fields: a patchwork with brightness 40..230, rows or speckle
    const long i = static_cast<long>( std::floor( x / fieldM ) ), j = static_cast<long>( std::floor( y / ( 0.7 * fieldM ) ) );
    const double base = 40.0 + 190.0 * paintedpair::hashUnit( i, j, 21 );
    if ( paintedpair::hashUnit( i, j, 22 ) < 0.5 )
    {
      const double angle = M_PI * paintedpair::hashUnit( i, j, 23 ), spacing = fieldM * ( 0.02 + 0.03 * paintedpair::hashUnit( i, j, 24 ) );
      return base + 8.0 * std::sin( ( x * std::cos( angle ) + y * std::sin( angle ) ) * 2.0 * M_PI / spacing );
    }
    const double grain = 0.02 * fieldM;
    return base + 16.0 * ( paintedpair::hashUnit( static_cast<long>( std::floor( x / grain ) ), static_cast<long>( std::floor( y / grain ) ), 25 ) - 0.5 );
  }

  inline PaintedRoadPair paintedRoadPair( const RoadScene &scene, uint32_t seed = 5 )
  {
    PaintedRoadPair pair;
    pair.gsdM = scene.gsdM;
    const int width = scene.width, height = scene.width * 3 / 4;
    pair.camera = paintedpair::paintedCamera( width, 0.006 );
    const Camera &camera = pair.camera;
    const double flyingM = pair.groundM + camera.f * scene.gsdM;
    const double extentX = width * scene.gsdM, extentY = height * scene.gsdM;
    for ( int k = 0; k < 2; ++k )
    {
      ExteriorOrientation e;
      e.projectionCentre = Eigen::Vector3d( k * 0.4 * extentX, 0.0, flyingM );
      e.omegaDeg = 0.4 * k;
      e.phiDeg = 0.3;
      e.kappaDeg = -0.6 * k;
      pair.exterior.push_back( e );
    }
    pair.roads = roadsOver( -0.5 * extentX, -0.5 * extentY, 1.4 * extentX, extentY, scene.widthsM );
    const double fieldM = std::max( 12.0, extentX / 7.0 );
    std::mt19937 random( seed );
    std::normal_distribution<double> noise( 0.0, 2.0 );
    for ( int k = 0; k < 2; ++k )
    {
      const OrientedImage image( camera, pair.exterior[k] );
      cv::Mat sum( height, width, CV_32F );
      for ( int r = 0; r < height; ++r )
        for ( int c = 0; c < width; ++c )
        {
          double total = 0.0;
          for ( int u = 0; u < 2; ++u )
            for ( int v = 0; v < 2; ++v )
            {
              const std::optional<Ray> ray = image.worldRayFromPixel( Eigen::Vector2d( c + 0.25 + 0.5 * u, r + 0.25 + 0.5 * v ) );
              const Eigen::Vector3d g = ray->origin + ( pair.groundM - ray->origin.z() ) / ray->direction.z() * ray->direction;
              total += groundGrey( pair.roads, fieldM, g.x(), g.y() );
            }
          sum.at<float>( r, c ) = static_cast<float>( total / 4.0 );
        }
      cv::GaussianBlur( sum, sum, cv::Size( 0, 0 ), 0.6 );
      cv::Mat grey( height, width, CV_8U );
      for ( int r = 0; r < height; ++r )
        for ( int c = 0; c < width; ++c )
          grey.at<uint8_t>( r, c ) = cv::saturate_cast<uint8_t>( sum.at<float>( r, c ) + noise( random ) );
      pair.grey.push_back( grey );
    }
    return pair;
  }

  //! A road's centre line in photo k, sampled every metre and cut to the parts inside both photos (`marginPx` from their edges).
  inline std::vector<PixelPolyline> truthInPhoto( const PaintedRoadPair &pair, int k, double marginPx )
  {
    std::vector<PixelPolyline> out;
    const OrientedImage a( pair.camera, pair.exterior[0] ), b( pair.camera, pair.exterior[1] );
    const OrientedImage &self = k == 0 ? a : b;
    const auto inside = [&]( const OrientedImage &image, const Eigen::Vector3d &g ) {
      const GroundProjection q = image.projectGroundToPixel( g );
      return q.pixelInImage.x() > marginPx && q.pixelInImage.y() > marginPx && q.pixelInImage.x() < pair.camera.width - marginPx &&
             q.pixelInImage.y() < pair.camera.height - marginPx;
    };
    for ( const PaintedRoad &road : pair.roads )
    {
      PixelPolyline current;
      for ( size_t i = 0; i + 1 < road.centre.size(); ++i )
      {
        const double length = ( road.centre[i + 1] - road.centre[i] ).norm();
        const int n = std::max( 1, static_cast<int>( length / std::max( 1.0, pair.gsdM ) ) );
        for ( int s = 0; s < n; ++s )
        {
          const Eigen::Vector2d xy = road.centre[i] + ( road.centre[i + 1] - road.centre[i] ) * s / n;
          const Eigen::Vector3d g( xy.x(), xy.y(), pair.groundM );
          if ( inside( a, g ) && inside( b, g ) )
            current.push_back( self.projectGroundToPixel( g ).pixelInImage );
          else if ( current.size() > 1 )
            out.push_back( std::move( current ) ), current.clear();
          else
            current.clear();
        }
      }
      if ( current.size() > 1 )
        out.push_back( std::move( current ) );
    }
    return out;
  }

} // namespace geostation::paintedroads

#endif // GEOSTATION_TESTS_PAINTEDROADS_H
