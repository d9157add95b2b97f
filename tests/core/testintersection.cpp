// Space intersection and ray / plane against exact synthetic truth.
#include <random>

#include <gtest/gtest.h>

#include "adjustment/intersection.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  std::vector<RayObservation> observe( const std::vector<std::unique_ptr<OrientedImage>> &images, const Eigen::Vector3d &point, size_t count, double sigmaPx,
                                       std::mt19937 *rng = nullptr, double noisePx = 0.0 )
  {
    std::normal_distribution<double> noise( 0.0, 1.0 );
    std::vector<RayObservation> out;
    for ( size_t i = 0; i < count; ++i )
    {
      const GroundProjection g = images[i]->projectGroundToPixel( point );
      EXPECT_TRUE( g.ok() && g.inFrame );
      Eigen::Vector2d pixel = g.pixelInImage;
      if ( rng )
        pixel += noisePx * Eigen::Vector2d( noise( *rng ), noise( *rng ) );
      out.push_back( { images[i].get(), pixel, sigmaPx } );
    }
    return out;
  }
} // namespace

TEST( Intersection, NoiseFreeRaysRecoverTheTruth )
{
  const auto images = vanrig::images();
  std::mt19937 rng( 1 );
  for ( size_t count = 2; count <= 6; ++count )
    for ( int trial = 0; trial < 20; ++trial )
    {
      const Eigen::Vector3d truth = vanrig::pointAhead( rng );
      const IntersectionSummary s = intersectRays( observe( images, truth, count, 0.5 ) );
      ASSERT_TRUE( s.ok() ) << s.message;
      EXPECT_LT( ( s.point - truth ).norm(), 1e-7 ) << count;
      EXPECT_LT( s.maxResidualPx, 1e-6 );
      EXPECT_EQ( s.redundancy, 2 * static_cast<int>( count ) - 3 );
      EXPECT_FALSE( s.grossError );
      EXPECT_GT( s.maxRayAngleDeg, 1.0 );
      EXPECT_LT( s.iterations, 8 );
    }
}

TEST( Intersection, ReportedSigmasMatchTheScatter )
{
  // 400 Monte Carlo trials with 0.5 px noise: the empirical standard deviation
  // of each coordinate must match the reported one within 0.8-1.25.
  const auto images = vanrig::images();
  std::mt19937 rng( 7 );
  const Eigen::Vector3d truth( 500000.8, 4400018.0, 101.2 );
  for ( size_t count : { size_t( 2 ), size_t( 4 ) } )
  {
    Eigen::Vector3d sumSquares = Eigen::Vector3d::Zero();
    Eigen::Vector3d reported = Eigen::Vector3d::Zero();
    const int trials = 400;
    for ( int t = 0; t < trials; ++t )
    {
      const IntersectionSummary s = intersectRays( observe( images, truth, count, 0.5, &rng, 0.5 ) );
      ASSERT_TRUE( s.ok() );
      sumSquares += ( s.point - truth ).cwiseAbs2();
      reported += s.sigmaM;
    }
    const Eigen::Vector3d empirical = ( sumSquares / trials ).cwiseSqrt();
    reported /= trials;
    for ( int k = 0; k < 3; ++k )
    {
      const double ratio = empirical[k] / reported[k];
      EXPECT_GT( ratio, 0.8 ) << "rays " << count << " axis " << k << " empirical " << empirical[k] << " reported " << reported[k];
      EXPECT_LT( ratio, 1.25 ) << "rays " << count << " axis " << k << " empirical " << empirical[k] << " reported " << reported[k];
    }
    // Along-track (Y, the depth) is the weak direction of a forward-looking van.
    EXPECT_GT( reported.y(), reported.x() );
  }
}

TEST( Intersection, AGrossErrorIsFlaggedOnTheRightRay )
{
  const auto images = vanrig::images();
  const Eigen::Vector3d truth( 499999.5, 4400020.0, 102.0 );
  std::vector<RayObservation> obs = observe( images, truth, 6, 0.5 );
  obs[4].pixelInImage += Eigen::Vector2d( 12.0, -6.0 );
  const IntersectionSummary s = intersectRays( obs );
  ASSERT_TRUE( s.ok() );
  EXPECT_TRUE( s.grossError );
  for ( int i = 0; i < 6; ++i )
    EXPECT_EQ( s.residuals[i].suspect, i == 4 ) << i;
  EXPECT_GT( s.maxResidualPx, 3.0 );
  EXPECT_GT( s.sigma0, 3.0 );

  // Two rays: the error shows, but no ray can be blamed.
  std::vector<RayObservation> pair = observe( images, truth, 2, 0.5 );
  pair[1].pixelInImage.y() += 15.0;
  const IntersectionSummary p = intersectRays( pair );
  ASSERT_TRUE( p.ok() );
  EXPECT_TRUE( p.grossError );
  EXPECT_FALSE( p.residuals[0].suspect || p.residuals[1].suspect );
}

TEST( Intersection, ExpectedFailuresAreReportedNotThrown )
{
  const auto images = vanrig::images();
  const Eigen::Vector3d truth( 500000.0, 4400020.0, 102.0 );
  std::vector<RayObservation> obs = observe( images, truth, 2, 0.5 );

  EXPECT_EQ( intersectRays( { obs[0] } ).status, IntersectionSummary::Status::TooFewRays );

  // The same ray twice: parallel.
  const IntersectionSummary parallel = intersectRays( { obs[0], obs[0] } );
  EXPECT_EQ( parallel.status, IntersectionSummary::Status::ParallelRays );
  EXPECT_NE( parallel.message.find( "parallel" ), std::string::npos );

  // Rays that diverge meet (in the least-squares sense) behind the cameras.
  std::vector<RayObservation> diverging = obs;
  diverging[0].pixelInImage.x() -= 300.0;
  diverging[1].pixelInImage.x() += 300.0;
  const IntersectionSummary behind = intersectRays( diverging );
  EXPECT_EQ( behind.status, IntersectionSummary::Status::BehindCamera ) << behind.message;

  obs[0].sigmaPx = 0.0;
  EXPECT_THROW( intersectRays( obs ), std::invalid_argument );
  obs[0].sigmaPx = 0.5;
  obs[0].image = nullptr;
  EXPECT_THROW( intersectRays( obs ), std::invalid_argument );
}

TEST( RayPlane, RoadPointsLandOnThePlaneWithHonestSigmas )
{
  const auto images = vanrig::images();
  std::mt19937 rng( 11 );
  std::normal_distribution<double> noise( 0.0, 1.0 );
  const Plane road = Plane::horizontal( 100.0 );
  for ( size_t i = 0; i < images.size(); ++i )
  {
    const Eigen::Vector3d truth( 500000.0 + ( static_cast<int>( i % 3 ) - 1 ) * 1.5, 4400015.0 + 5.0 * ( i / 3 ), 100.0 );
    const GroundProjection g = images[i]->projectGroundToPixel( truth );
    ASSERT_TRUE( g.inFrame );
    const PlaneIntersectionSummary exact = intersectRayWithPlane( { images[i].get(), g.pixelInImage, 0.5 }, road, 0.03 );
    ASSERT_TRUE( exact.ok() );
    EXPECT_LT( ( exact.point - truth ).norm(), 1e-7 );

    // Monte Carlo with pixel and plane-height noise.
    Eigen::Vector3d sumSquares = Eigen::Vector3d::Zero();
    const int trials = 400;
    for ( int t = 0; t < trials; ++t )
    {
      const Eigen::Vector2d pixel = g.pixelInImage + 0.5 * Eigen::Vector2d( noise( rng ), noise( rng ) );
      const PlaneIntersectionSummary s = intersectRayWithPlane( { images[i].get(), pixel, 0.5 }, Plane::horizontal( 100.0 + 0.03 * noise( rng ) ), 0.03 );
      ASSERT_TRUE( s.ok() );
      sumSquares += ( s.point - truth ).cwiseAbs2();
    }
    const Eigen::Vector3d empirical = ( sumSquares / trials ).cwiseSqrt();
    for ( int k = 0; k < 2; ++k ) // Z is the plane's own sigma
    {
      const double ratio = empirical[k] / exact.sigmaM[k];
      EXPECT_GT( ratio, 0.8 ) << "image " << i << " axis " << k;
      EXPECT_LT( ratio, 1.25 ) << "image " << i << " axis " << k;
    }
    EXPECT_NEAR( exact.sigmaM.z(), 0.03, 1e-9 );
  }
}

TEST( RayPlane, GrazingRaysAreWeakAndBackwardRaysMiss )
{
  const auto images = vanrig::images();
  const OrientedImage &image = *images[1];
  const Plane road = Plane::horizontal( 100.0 );
  const GroundProjection nearPoint = image.projectGroundToPixel( { 500000.0, 4400010.0, 100.0 } );
  const GroundProjection farPoint = image.projectGroundToPixel( { 500000.0, 4400060.0, 100.0 } );
  const PlaneIntersectionSummary nearHit = intersectRayWithPlane( { &image, nearPoint.pixelInImage, 0.5 }, road );
  const PlaneIntersectionSummary farHit = intersectRayWithPlane( { &image, farPoint.pixelInImage, 0.5 }, road );
  ASSERT_TRUE( nearHit.ok() && farHit.ok() );
  EXPECT_GT( farHit.sigmaM.y(), 10.0 * nearHit.sigmaM.y() );
  EXPECT_LT( farHit.incidenceDeg, nearHit.incidenceDeg );

  // A pixel above the horizon: the road plane is behind the camera along it.
  const PlaneIntersectionSummary sky = intersectRayWithPlane( { &image, { 640.0, 5.0 }, 0.5 }, road );
  EXPECT_EQ( sky.status, PlaneIntersectionSummary::Status::BehindCamera );
}
