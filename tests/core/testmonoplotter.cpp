// Monoplotting: an oblique image over synthetic terrain, against exact truth.
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "dem/monoplotter.h"
#include "syntheticterrain.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  using syntheticterrain::kX0;
  using syntheticterrain::kY0;

  struct Scene
  {
    std::string path;
    std::unique_ptr<Dem> dem;
    CrsTransform same { "EPSG:32633", "EPSG:32633" };
    std::unique_ptr<OrientedImage> image;
    Scene()
    {
      path = syntheticterrain::tempPath( "mono" );
      syntheticterrain::writeTerrain( path, 500 );
      dem = std::make_unique<Dem>( path );
      // An oblique photo from a hill-top mast: 60 m above the terrain, looking north and down.
      const Eigen::Vector3d centre( kX0 + 500.0, kY0 - 950.0, *dem->heightAt( kX0 + 500.0, kY0 - 950.0 ) + 60.0 );
      ExteriorOrientation eo = vanrig::lookAt( centre, centre + Eigen::Vector3d( 0.0, 300.0, -120.0 ) );
      eo.sigma = ExteriorSigma { 0.05, 0.05, 0.05, 0.01, 0.01, 0.01 };
      image = std::make_unique<OrientedImage>( vanrig::camera( DistortionModel::OpenCV ), eo );
    }
    ~Scene() { std::filesystem::remove( path ); }
  };

  Scene &scene()
  {
    static Scene s;
    return s;
  }
} // namespace

TEST( Monoplotter, ImageGroundImageRoundTripBelowAHundredthOfAPixel )
{
  Scene &s = scene();
  const Monoplotter mono( *s.image, *s.dem, s.same );
  int hits = 0;
  for ( double row = 300.0; row < 960.0; row += 40.0 )
    for ( double col = 10.0; col < 1280.0; col += 60.0 )
    {
      const MonoplotPoint g = mono.imageToGround( { col, row }, false );
      if ( !g.ok() )
        continue;
      ++hits;
      EXPECT_NEAR( g.world.z(), *s.dem->heightAt( g.world.x(), g.world.y() ), 1e-3 );
      const MapPointInImage back = mono.groundToImage( g.world );
      ASSERT_TRUE( back.projection.ok() );
      EXPECT_LT( ( back.projection.pixelInImage - Eigen::Vector2d( col, row ) ).norm(), 0.01 ) << col << "," << row;
      EXPECT_TRUE( back.visible ) << col << "," << row;
    }
  EXPECT_GT( hits, 200 );
}

TEST( Monoplotter, TruthVerticesComeBackWithinAMillimetre )
{
  Scene &s = scene();
  const Monoplotter mono( *s.image, *s.dem, s.same );
  std::mt19937 rng( 1 );
  std::uniform_real_distribution<double> x( kX0 + 300, kX0 + 700 ), y( kY0 - 850, kY0 - 600 );
  int checked = 0;
  for ( int i = 0; i < 200; ++i )
  {
    const Eigen::Vector3d truth( x( rng ), y( rng ), 0.0 );
    const Eigen::Vector3d onSurface( truth.x(), truth.y(), *s.dem->heightAt( truth.x(), truth.y() ) );
    const MapPointInImage seen = mono.groundToImage( onSurface );
    if ( !seen.visible )
      continue;
    const MonoplotPoint g = mono.imageToGround( seen.projection.pixelInImage, false );
    ASSERT_TRUE( g.ok() );
    EXPECT_LT( ( g.world - onSurface ).norm(), 1e-3 );
    ++checked;
  }
  EXPECT_GT( checked, 100 );
}

TEST( Monoplotter, ReportedSigmasMatchTheScatterAndShowWeakGrazingRays )
{
  Scene &s = scene();
  std::normal_distribution<double> noise( 0.0, 1.0 );
  std::mt19937 rng( 2 );
  const ExteriorOrientation trueEo = s.image->exterior();
  double nearSigma = 0.0, farSigma = 0.0;
  for ( const double ahead : { 150.0, 450.0 } )
  {
    const Eigen::Vector3d p( kX0 + 510.0, kY0 - 950.0 + ahead, 0.0 );
    const Eigen::Vector3d truth( p.x(), p.y(), *s.dem->heightAt( p.x(), p.y() ) );
    const Eigen::Vector2d pixel = s.image->projectGroundToPixel( truth ).pixelInImage;
    Eigen::Vector3d sumSquares = Eigen::Vector3d::Zero(), reported = Eigen::Vector3d::Zero();
    const int trials = 200;
    for ( int t = 0; t < trials; ++t )
    {
      ExteriorOrientation eo = trueEo;
      eo.projectionCentre += 0.05 * Eigen::Vector3d( noise( rng ), noise( rng ), noise( rng ) );
      eo.omegaDeg += 0.01 * noise( rng );
      eo.phiDeg += 0.01 * noise( rng );
      eo.kappaDeg += 0.01 * noise( rng );
      const OrientedImage noisy( s.image->camera(), eo );
      const Monoplotter mono( noisy, *s.dem, s.same );
      const MonoplotPoint g = mono.imageToGround( pixel + 0.5 * Eigen::Vector2d( noise( rng ), noise( rng ) ) );
      ASSERT_TRUE( g.ok() ) << g.message;
      sumSquares += ( g.world - truth ).cwiseAbs2();
      reported += g.sigmaM;
    }
    const Eigen::Vector3d empirical = ( sumSquares / trials ).cwiseSqrt();
    reported /= trials;
    for ( int k = 0; k < 3; ++k )
    {
      EXPECT_GT( empirical[k] / reported[k], 0.8 ) << ahead << " m, axis " << k << ": empirical " << empirical[k] << " reported " << reported[k];
      EXPECT_LT( empirical[k] / reported[k], 1.25 ) << ahead << " m, axis " << k << ": empirical " << empirical[k] << " reported " << reported[k];
    }
    ( ahead < 300 ? nearSigma : farSigma ) = reported.y();
  }
  // Along the line of sight, a far (grazing) ray is much weaker.
  EXPECT_GT( farSigma, 3.0 * nearSigma );
}

TEST( Monoplotter, HiddenPointsAreNotVisible )
{
  Scene &s = scene();
  const Monoplotter mono( *s.image, *s.dem, s.same );
  std::mt19937 rng( 3 );
  std::uniform_real_distribution<double> x( kX0 + 200, kX0 + 800 ), y( kY0 - 850, kY0 - 20 );
  int visible = 0, hidden = 0;
  for ( int i = 0; i < 400; ++i )
  {
    const Eigen::Vector3d p( x( rng ), y( rng ), 0.0 );
    const Eigen::Vector3d onSurface( p.x(), p.y(), *s.dem->heightAt( p.x(), p.y() ) );
    const MapPointInImage seen = mono.groundToImage( onSurface );
    if ( !seen.projection.inFrame )
      continue;
    // Visible exactly when the pixel's ray first meets the terrain at the point.
    const MonoplotPoint back = mono.imageToGround( seen.projection.pixelInImage, false );
    const bool firstHitIsThePoint = back.ok() && ( back.world - onSurface ).norm() < 0.05;
    EXPECT_EQ( seen.visible, firstHitIsThePoint ) << onSurface.transpose();
    ( seen.visible ? visible : hidden ) += 1;
  }
  EXPECT_GT( visible, 20 );
  EXPECT_GT( hidden, 5 );
}

TEST( Monoplotter, LinesAreDensifiedBothWays )
{
  Scene &s = scene();
  const Monoplotter mono( *s.image, *s.dem, s.same );
  const std::vector<MonoplotPoint> draped = mono.imageLineToGround( { { 200.0, 700.0 }, { 1100.0, 650.0 } }, 5.0, false );
  ASSERT_GT( draped.size(), 180u );
  for ( size_t i = 0; i < draped.size(); ++i )
  {
    ASSERT_TRUE( draped[i].ok() );
    EXPECT_NEAR( draped[i].world.z(), *s.dem->heightAt( draped[i].world.x(), draped[i].world.y() ), 1e-3 );
    if ( i > 0 )
    {
      EXPECT_LE( ( draped[i].pixelInImage - draped[i - 1].pixelInImage ).norm(), 5.0 + 1e-9 );
    }
  }

  // A straight map line across the hills, draped: consecutive pixels within 4 px.
  const Eigen::Vector3d a( kX0 + 400.0, kY0 - 750.0, 0.0 ), b( kX0 + 620.0, kY0 - 700.0, 0.0 );
  const std::vector<MapPointInImage> curve = mono.groundLineToImage( { { a.x(), a.y(), *s.dem->heightAt( a.x(), a.y() ) }, { b.x(), b.y(), *s.dem->heightAt( b.x(), b.y() ) } }, 4.0, true );
  ASSERT_GT( curve.size(), 10u );
  for ( size_t i = 1; i < curve.size(); ++i )
    EXPECT_LE( ( curve[i].projection.pixelInImage - curve[i - 1].projection.pixelInImage ).norm(), 4.0 + 1e-9 );
  EXPECT_THROW( mono.imageLineToGround( { { 1, 1 }, { 2, 2 } }, 0.0 ), std::invalid_argument );
}

TEST( Monoplotter, ResolvedRunsOfACutLineLongestFirst )
{
  // x along the ground (m); false: the ray met a hole
  const std::vector<std::pair<double, bool>> points { { 0, true }, { 1, true }, { 2, false }, { 3, true }, { 4, true }, { 10, true }, { 11, false },
    { 12, true }, { 13, false } };
  std::vector<MonoplotPoint> line;
  for ( const auto &[x, hit] : points )
  {
    MonoplotPoint p;
    p.status = hit ? DemIntersection::Status::Hit : DemIntersection::Status::Hole;
    p.world = Eigen::Vector3d( x, 0, 0 );
    line.push_back( p );
  }
  const std::vector<std::pair<size_t, size_t>> runs = resolvedRuns( line );
  // 3-4-10 (7 m), then 0-1 (1 m); the lone resolved point 12 is no run
  ASSERT_EQ( runs.size(), 2u );
  EXPECT_EQ( runs[0], std::make_pair( size_t( 3 ), size_t( 5 ) ) );
  EXPECT_EQ( runs[1], std::make_pair( size_t( 0 ), size_t( 1 ) ) );
  EXPECT_TRUE( resolvedRuns( std::vector<MonoplotPoint>( 3 ) ).empty() );
}
