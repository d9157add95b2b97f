// Multi-station vertices (core/tracing/multistationvertices) on a scene built
// here, not by the simulator: a painted stripe on a flat road rendered into
// the pairs of three stations 10 m apart; the block's poses are the true
// ones with GNSS/INS errors drawn anew in every trial, so the refined
// vertices' errors can be compared with their covariances.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "adjustment/intersection.h"
#include "tracing/multistationvertices.h"
#include "stripedroad.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  using namespace stripedroad;

  //! The camera `side` (-1 left, +1 right) of the station at `y`, 2.65 m above the road, 7 degrees down.
  ExteriorOrientation trueExterior( double y, int side )
  {
    const Eigen::Vector3d centre( side * 1.0, y, kRoadZ + 2.65 );
    return vanrig::lookAt( centre, centre + Eigen::Vector3d( 0.0, 30.0, -30.0 * std::tan( 7.0 * M_PI / 180.0 ) ) );
  }

  //! A bright stripe at x = kStripeX on dark asphalt, grey noise 1.
  cv::Mat render( const OrientedImage &image, std::mt19937 &rng ) { return stripedroad::render( image, fullStripe, 1.0, rng ); }

  struct Station
  {
    std::vector<ExteriorOrientation> truth; // left, right
    std::vector<cv::Mat> greys;
  };

  //! The own station (y = 0), then 10 and 20 m behind, each pair rendered with its true orientation.
  std::vector<Station> threeStations( const Camera &camera, std::mt19937 &rng )
  {
    std::vector<Station> stations;
    for ( const double y : { 0.0, -10.0, -20.0 } )
    {
      Station s;
      for ( const int side : { -1, 1 } )
      {
        s.truth.push_back( trueExterior( y, side ) );
        s.greys.push_back( render( OrientedImage( camera, s.truth.back() ), rng ) );
      }
      stations.push_back( s );
    }
    return stations;
  }
}

TEST( MultiStationVertices, PoseErrorsAveragedOverStationsWithHonestSigmas )
{
  std::mt19937 rng( 11 );
  const Camera camera = vanCamera();
  const std::vector<Station> stations = threeStations( camera, rng );
  const ExteriorSigma sigma { 0.02, 0.02, 0.03, 0.004, 0.004, 0.01 };
  std::normal_distribution<double> gauss( 0.0, 1.0 );
  const double pixelSigma = 0.2;

  double sumPair = 0.0, sumMulti = 0.0, sumZ = 0.0, sumZ2 = 0.0;
  int n = 0, observations = 0;
  for ( int trial = 0; trial < 40; ++trial )
  {
    // the block's poses: each station's rig shifted and turned as a whole
    std::vector<std::vector<OrientedImage>> known;
    for ( const Station &s : stations )
    {
      const Eigen::Vector3d shift( sigma.x * gauss( rng ), sigma.y * gauss( rng ), sigma.z * gauss( rng ) );
      const Eigen::Vector3d turn( sigma.omegaDeg * gauss( rng ), sigma.phiDeg * gauss( rng ), sigma.kappaDeg * gauss( rng ) );
      std::vector<OrientedImage> images;
      for ( ExteriorOrientation e : s.truth )
      {
        e.projectionCentre += shift;
        e.omegaDeg += turn.x();
        e.phiDeg += turn.y();
        e.kappaDeg += turn.z();
        e.sigma = sigma;
        images.push_back( OrientedImage( camera, e ) );
      }
      known.push_back( images );
    }
    const auto view = [&]( size_t s )
    {
      return StationView { "S" + std::to_string( s ), { { "L" + std::to_string( s ), &known[s][0], &stations[s].greys[0] }, { "R" + std::to_string( s ), &known[s][1], &stations[s].greys[1] } } };
    };
    // the own pair's measurements of points on the stripe 8-14 m ahead: where the true cameras see them
    std::vector<LineVertex3d> vertices;
    std::vector<Eigen::Vector3d> truth;
    for ( const double y : { 8.0, 10.0, 12.0, 14.0 } )
    {
      const Eigen::Vector3d p( kStripeX, y, kRoadZ );
      const OrientedImage left( camera, stations[0].truth[0] ), right( camera, stations[0].truth[1] );
      const Eigen::Vector2d inLeft = left.projectGroundToPixel( p ).pixelInImage + pixelSigma * Eigen::Vector2d( gauss( rng ), gauss( rng ) );
      const Eigen::Vector2d inRight = right.projectGroundToPixel( p ).pixelInImage + pixelSigma * Eigen::Vector2d( gauss( rng ), gauss( rng ) );
      const Eigen::Vector2d along = ( right.projectGroundToPixel( p + Eigen::Vector3d::UnitY() ).pixelInImage - right.projectGroundToPixel( p ).pixelInImage ).normalized();
      const IntersectionSummary pair = intersectRays( { { &known[0][0], inLeft, pixelSigma }, { &known[0][1], inRight, pixelSigma } } );
      ASSERT_TRUE( pair.ok() );
      LineVertex3d v;
      v.point = pair.point;
      v.covariance = pair.covariance + rigPoseCovariance( known[0][0].exterior(), pair.point, 0.5 * ( known[0][0].exterior().projectionCentre + known[0][1].exterior().projectionCentre ) );
      v.pixelInReference = inLeft;
      v.pixelInPartner = inRight + 3.0 * along; // anywhere on the partner's line
      v.sigmaReferencePx = v.sigmaPartnerLinePx = pixelSigma;
      v.partnerLineDirection = along;
      vertices.push_back( v );
      truth.push_back( p );
    }
    const std::vector<LineVertex3d> pairOnly = vertices;
    const MultiStationSummary summary = refineFromOtherStations( vertices, view( 0 ), { view( 1 ), view( 2 ) }, LineProfile { LineKind::BrightStripe, 1, 0.0, 140.0 },
                                                                 0.15 * camera.f, Eigen::Vector3d::UnitY() );
    ASSERT_EQ( vertices.size(), truth.size() ) << "no vertex is dropped";
    EXPECT_EQ( summary.vertices, 4 );
    observations += summary.observations;
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      // across the stripe (x) and in height (z): along it a line has nothing to measure
      for ( const int axis : { 0, 2 } )
      {
        const double e = vertices[i].point( axis ) - truth[i]( axis ), pairError = pairOnly[i].point( axis ) - truth[i]( axis );
        sumMulti += e * e;
        sumPair += pairError * pairError;
        const double z = e / std::sqrt( vertices[i].covariance( axis, axis ) );
        sumZ += z;
        sumZ2 += z * z;
        ++n;
      }
      EXPECT_LE( vertices[i].covariance( 0, 0 ), pairOnly[i].covariance( 0, 0 ) );
      EXPECT_EQ( vertices[i].others.size(), 4u ) << "the stripe in both images of the two stations behind";
    }
  }
  const double rmsPair = std::sqrt( sumPair / n ), rmsMulti = std::sqrt( sumMulti / n );
  const double sd = std::sqrt( ( sumZ2 - sumZ * sumZ / n ) / ( n - 1 ) );
  std::printf( "across / height RMS: pair %.1f mm, three stations %.1f mm (%d observations from the stations behind); normalised sd %.2f\n", 1000 * rmsPair,
               1000 * rmsMulti, observations, sd );
  // three independent poses: the pose part falls by up to sqrt(3)
  EXPECT_LT( rmsMulti, 0.8 * rmsPair );
  EXPECT_GT( sd, 0.75 );
  EXPECT_LT( sd, 1.3 );
}

TEST( MultiStationVertices, AWrongConjugateIsLeftOutOrPutRight )
{
  std::mt19937 rng( 5 );
  const Camera camera = vanCamera();
  const ExteriorSigma sigma { 0.02, 0.02, 0.03, 0.004, 0.004, 0.01 };
  const std::vector<Station> stations = threeStations( camera, rng );
  std::vector<std::vector<OrientedImage>> images; // the true orientation, with GNSS/INS sigmas
  for ( const Station &s : stations )
  {
    images.emplace_back();
    for ( ExteriorOrientation e : s.truth )
    {
      e.sigma = sigma;
      images.back().push_back( OrientedImage( camera, e ) );
    }
  }
  const auto view = [&]( size_t s ) { return StationView { "S" + std::to_string( s ), { { "L", &images[s][0], &stations[s].greys[0] }, { "R", &images[s][1], &stations[s].greys[1] } } }; };
  int dropped = 0, putRight = 0, cases = 0;
  for ( const double y : { 8.0, 10.0, 12.0, 14.0 } )
    for ( const double shift : { -2.0, 2.0 } )
    {
      // the partner's conjugate a few pixels off along the epipolar line (a wrong crossing)
      const Eigen::Vector3d p( kStripeX, y, kRoadZ );
      const Eigen::Vector2d inLeft = images[0][0].projectGroundToPixel( p ).pixelInImage;
      const Eigen::Vector2d inRight = images[0][1].projectGroundToPixel( p ).pixelInImage + Eigen::Vector2d( shift, 0.0 );
      const Eigen::Vector2d along =
        ( images[0][1].projectGroundToPixel( p + Eigen::Vector3d::UnitY() ).pixelInImage - images[0][1].projectGroundToPixel( p ).pixelInImage ).normalized();
      const IntersectionSummary wrong = intersectRays( { { &images[0][0], inLeft, 0.2 }, { &images[0][1], inRight, 0.2 } } );
      ASSERT_TRUE( wrong.ok() );
      LineVertex3d v;
      v.point = wrong.point;
      v.covariance = wrong.covariance + rigPoseCovariance( images[0][0].exterior(), wrong.point, Eigen::Vector3d( 0.0, 0.0, kRoadZ + 2.65 ) );
      v.pixelInReference = inLeft;
      v.pixelInPartner = inRight;
      v.sigmaReferencePx = v.sigmaPartnerLinePx = 0.2;
      v.partnerLineDirection = along;
      std::vector<LineVertex3d> vertices { v };
      const MultiStationSummary summary = refineFromOtherStations( vertices, view( 0 ), { view( 1 ), view( 2 ) }, LineProfile { LineKind::BrightStripe, 1, 0.0, 140.0 },
                                                                   0.15 * camera.f, Eigen::Vector3d::UnitY() );
      const double before = std::hypot( wrong.point.x() - p.x(), wrong.point.z() - p.z() );
      const double after = vertices.empty() ? 0.0 : std::hypot( vertices.front().point.x() - p.x(), vertices.front().point.z() - p.z() );
      std::printf( "conjugate %+.0f px off at %.0f m: %.3f m off across / in height; %s %.3f m\n", shift, y, before, vertices.empty() ? "left out" : "then", after );
      EXPECT_GT( before, 0.03 );
      ++cases;
      dropped += summary.dropped;
      putRight += !vertices.empty() && after < 0.5 * before ? 1 : 0;
      EXPECT_TRUE( vertices.empty() || after < before ) << y << " " << shift;
    }
  std::printf( "%d of %d left out, %d put right\n", dropped, cases, putRight );
  EXPECT_GE( dropped + putRight, cases - 1 );
}
