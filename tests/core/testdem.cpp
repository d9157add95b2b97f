// DEM access and ray / DEM intersection on synthetic terrain.
#include <filesystem>
#include <functional>
#include <random>

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include "dem/demintersection.h"
#include "syntheticterrain.h"

using namespace geostation;

namespace
{
  using syntheticterrain::kX0;
  using syntheticterrain::kY0;
  using syntheticterrain::tempPath;
  double terrain( double x, double y ) { return syntheticterrain::height( x, y ); }

  std::string writeDem( const std::string &name, const char *crs, const std::array<double, 6> &gt, int w, int h,
                        const std::function<double( double, double )> &value, const std::function<bool( int, int )> &hole = nullptr )
  {
    const std::string path = tempPath( name );
    syntheticterrain::writeDem( path, crs, gt, w, h, value, hole );
    return path;
  }

  std::string projectedDem( const std::function<bool( int, int )> &hole = nullptr, const std::string &name = "dem" )
  {
    return writeDem( name, "EPSG:32633", { kX0, 2.0, 0.0, kY0, 0.0, -2.0 }, 500, 500, terrain, hole );
  }

  //! The test terrain sampled on a lon/lat grid over the UTM area (about 2 m cells).
  std::string geographicDem( const std::string &name )
  {
    const CrsTransform toUtm( "EPSG:4326", "EPSG:32633" ), toGeographic( "EPSG:32633", "EPSG:4326" );
    const Eigen::Vector3d corner = toGeographic.transform( { kX0 - 50.0, kY0 + 50.0, 0.0 } );
    const double cellDeg = 2.0 / 111000.0;
    return writeDem( name, "EPSG:4326", { corner.x(), cellDeg * 1.4, 0.0, corner.y(), 0.0, -cellDeg }, 800, 600,
    [&]( double lon, double lat ) { const Eigen::Vector3d p = toUtm.transform( { lon, lat, 0.0 } ); return terrain( p.x(), p.y() ); } );
  }

  //! Brute force: first sign change of the height above the DEM every `step` metres, then bisection.
  std::optional<double> bruteForceRange( const Ray &ray, const Dem &dem, double maxRange, double step )
  {
    double previous = -1.0;
    for ( double t = 0.0; t <= maxRange; t += step )
    {
      const Eigen::Vector3d p = ray.origin + t * ray.direction;
      const std::optional<double> h = dem.heightAt( p.x(), p.y() );
      if ( !h )
        return std::nullopt;
      if ( p.z() - *h <= 0.0 )
      {
        double lo = previous, hi = t;
        for ( int i = 0; i < 60; ++i )
        {
          const double mid = 0.5 * ( lo + hi );
          const Eigen::Vector3d q = ray.origin + mid * ray.direction;
          ( q.z() - *dem.heightAt( q.x(), q.y() ) > 0.0 ? lo : hi ) = mid;
        }
        return 0.5 * ( lo + hi );
      }
      previous = t;
    }
    return std::nullopt;
  }
} // namespace

TEST( Dem, HeightsSitAtCellCentresAndInterpolateBilinearly )
{
  const std::string path = projectedDem();
  const Dem dem( path );
  EXPECT_FALSE( dem.isGeographic() );
  // Centre of cell (10, 20) is (kX0 + 21, kY0 - 41).
  EXPECT_NEAR( *dem.heightAt( kX0 + 21.0, kY0 - 41.0 ), static_cast<float>( terrain( kX0 + 21.0, kY0 - 41.0 ) ), 1e-9 );
  const double mid = *dem.heightAt( kX0 + 22.0, kY0 - 42.0 ); // between four centres
  const auto stored = []( double x, double y ) { return static_cast<double>( static_cast<float>( terrain( x, y ) ) ); };
  const double mean = ( stored( kX0 + 21, kY0 - 41 ) + stored( kX0 + 23, kY0 - 41 ) + stored( kX0 + 21, kY0 - 43 ) + stored( kX0 + 23, kY0 - 43 ) ) / 4.0;
  EXPECT_NEAR( mid, mean, 1e-9 );
  EXPECT_TRUE( dem.heightAt( kX0 + 1.0, kY0 - 1.0 ).has_value() );      // first centre
  EXPECT_FALSE( dem.heightAt( kX0 + 0.9, kY0 - 1.0 ).has_value() );     // outer half cell
  EXPECT_FALSE( dem.heightAt( kX0 + 2000.0, kY0 - 1.0 ).has_value() );
  std::filesystem::remove( path );
}

TEST( DemIntersection, NadirRaysLandOnTheSurface )
{
  const std::string path = projectedDem();
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  EXPECT_TRUE( same.isIdentity() );
  std::mt19937 rng( 1 );
  std::uniform_real_distribution<double> x( kX0 + 5, kX0 + 995 ), y( kY0 - 995, kY0 - 5 );
  for ( int i = 0; i < 300; ++i )
  {
    const Ray ray { { x( rng ), y( rng ), 900.0 }, { 0.0, 0.0, -1.0 } };
    const DemIntersection hit = intersectRayWithDem( ray, dem, same );
    ASSERT_TRUE( hit.hit() ) << hit.message;
    EXPECT_NEAR( hit.point.z(), *dem.heightAt( hit.point.x(), hit.point.y() ), 1e-3 );
    EXPECT_NEAR( hit.point.x(), ray.origin.x(), 1e-9 );
    EXPECT_LT( hit.steps, 40 );
  }
  std::filesystem::remove( path );
}

TEST( DemIntersection, GrazingRaysFromNearTheGroundFindTheFirstCrossing )
{
  const std::string path = projectedDem();
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  std::mt19937 rng( 2 );
  std::uniform_real_distribution<double> azimuth( 0.0, 2 * M_PI ), dip( 0.3, 4.0 ), pos( 150.0, 850.0 );
  int hits = 0;
  for ( int i = 0; i < 60; ++i )
  {
    const double cx = kX0 + pos( rng ), cy = kY0 - pos( rng );
    const double a = azimuth( rng ), down = dip( rng ) * M_PI / 180.0;
    const Ray ray { { cx, cy, *dem.heightAt( cx, cy ) + 1.7 }, Eigen::Vector3d( std::sin( a ) * std::cos( down ), std::cos( a ) * std::cos( down ), -std::sin( down ) ) };
    const DemIntersection hit = intersectRayWithDem( ray, dem, same );
    const std::optional<double> expected = bruteForceRange( ray, dem, 1500.0, 0.02 );
    ASSERT_EQ( hit.hit(), expected.has_value() ) << i << " " << hit.message;
    if ( !expected )
      continue;
    ++hits;
    EXPECT_NEAR( hit.rangeM, *expected, 0.005 ) << "ray " << i;
    EXPECT_NEAR( hit.point.z(), *dem.heightAt( hit.point.x(), hit.point.y() ), 1e-3 );
  }
  EXPECT_GT( hits, 30 );
  std::filesystem::remove( path );
}

TEST( DemIntersection, MissesAreReportedNeverAWrongPoint )
{
  const std::string path = projectedDem();
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const Eigen::Vector3d c( kX0 + 500, kY0 - 500, 0.0 );
  const double ground = *dem.heightAt( c.x(), c.y() );
  const DemIntersection sky = intersectRayWithDem( { { c.x(), c.y(), ground + 2 }, Eigen::Vector3d( 1, 0, 0.2 ).normalized() }, dem, same );
  EXPECT_EQ( sky.status, DemIntersection::Status::Miss );
  const DemIntersection below = intersectRayWithDem( { { c.x(), c.y(), ground - 1 }, { 0, 0, -1 } }, dem, same );
  EXPECT_EQ( below.status, DemIntersection::Status::BelowSurface );
  // Starting outside the DEM, flying in and hitting it is fine; flying away is a miss.
  const DemIntersection in = intersectRayWithDem( { { kX0 - 300, kY0 - 500, 400 }, Eigen::Vector3d( 1, 0, -0.5 ).normalized() }, dem, same );
  EXPECT_TRUE( in.hit() ) << in.message;
  const DemIntersection away = intersectRayWithDem( { { kX0 - 300, kY0 - 500, 400 }, Eigen::Vector3d( -1, 0, -0.5 ).normalized() }, dem, same );
  EXPECT_EQ( away.status, DemIntersection::Status::Miss );
  std::filesystem::remove( path );
}

TEST( DemIntersection, GridTraversalAgreesWithBruteForceForAllKindsOfRays )
{
  // Rays from inside and outside the DEM, steep and shallow, rising, level,
  // along the grid axes and through cell corners, on small tiles so that
  // many tile and block borders are crossed.
  const std::string path = projectedDem( nullptr, "kinds" );
  DemOptions small;
  small.tileSize = 16;
  small.cacheTiles = 9;
  const Dem dem( path, small );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  std::mt19937 rng( 7 );
  std::uniform_real_distribution<double> pos( -100.0, 1100.0 ), azimuth( 0.0, 2 * M_PI ), dip( -10.0, 60.0 ), above( 0.5, 80.0 );
  const std::vector<Eigen::Vector2d> axes { { 1, 0 }, { -1, 0 }, { 0, 1 }, { 0, -1 }, { M_SQRT1_2, M_SQRT1_2 } };
  int hits = 0, misses = 0;
  for ( int i = 0; i < 400; ++i )
  {
    const double x = kX0 + pos( rng ), y = kY0 - pos( rng );
    // every fifth ray starts on a cell corner and runs along an axis or the diagonal
    const bool onGrid = i % 5 == 0;
    const double ox = onGrid ? kX0 + 1.0 + 2.0 * std::round( ( x - kX0 - 1.0 ) / 2.0 ) : x;
    const double oy = onGrid ? kY0 - 1.0 - 2.0 * std::round( ( kY0 - 1.0 - y ) / 2.0 ) : y;
    const std::optional<double> ground = dem.heightAt( ox, oy );
    const double oz = ( ground ? *ground : terrain( ox, oy ) ) + above( rng );
    const double a = azimuth( rng ), down = ( i % 7 == 3 ? 90.0 : ( i % 11 == 5 ? 0.0 : dip( rng ) ) ) * M_PI / 180.0;
    const Eigen::Vector2d h = onGrid ? axes[( i / 5 ) % axes.size()] : Eigen::Vector2d( std::sin( a ), std::cos( a ) );
    const Ray ray { { ox, oy, oz }, Eigen::Vector3d( h.x() * std::cos( down ), h.y() * std::cos( down ), -std::sin( down ) ) };
    const DemIntersection hit = intersectRayWithDem( ray, dem, same );
    // Brute force from where the ray is over the DEM (a start outside it is walked in).
    double t0 = 0.0;
    while ( t0 < 3000.0 && !dem.heightAt( ray.origin.x() + t0 * ray.direction.x(), ray.origin.y() + t0 * ray.direction.y() ) )
      t0 += 0.01;
    std::optional<double> expected;
    if ( t0 < 3000.0 )
    {
      const Ray entered { ray.origin + t0 * ray.direction, ray.direction };
      if ( const std::optional<double> range = bruteForceRange( entered, dem, 3000.0, 0.01 ) )
        if ( *range > 1e-3 ) // not already below where it comes over the DEM
          expected = t0 + *range;
    }
    ASSERT_EQ( hit.hit(), expected.has_value() ) << "ray " << i << ": " << hit.message << " range " << hit.rangeM << " expected " << ( expected ? *expected : -1.0 );
    if ( !expected )
    {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_NEAR( hit.rangeM, *expected, 0.01 ) << "ray " << i;
    EXPECT_NEAR( hit.point.z(), *dem.heightAt( hit.point.x(), hit.point.y() ), 1e-3 ) << "ray " << i;
  }
  EXPECT_GT( hits, 150 );
  EXPECT_GT( misses, 30 );
  std::filesystem::remove( path );
}

TEST( DemIntersection, ARayInAnotherCrsIsFollowedByChordsToTheSameCrossing )
{
  // EPSG:25833 and EPSG:32633 coincide numerically but are not the same CRS:
  // the chord-by-chord traversal (for DEMs in another CRS) runs on the same
  // rays as the straight one.
  const std::string path = projectedDem( nullptr, "paths" );
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" ), other( "EPSG:32633", "EPSG:25833" );
  ASSERT_FALSE( other.isIdentity() );
  std::mt19937 rng( 8 );
  std::uniform_real_distribution<double> pos( 100.0, 900.0 ), azimuth( 0.0, 2 * M_PI ), dip( 1.0, 89.0 ), above( 1.0, 300.0 );
  for ( int i = 0; i < 100; ++i )
  {
    const double x = kX0 + pos( rng ), y = kY0 - pos( rng ), a = azimuth( rng ), down = dip( rng ) * M_PI / 180.0;
    const Ray ray { { x, y, *dem.heightAt( x, y ) + above( rng ) }, Eigen::Vector3d( std::sin( a ) * std::cos( down ), std::cos( a ) * std::cos( down ), -std::sin( down ) ) };
    const DemIntersection straight = intersectRayWithDem( ray, dem, same ), chords = intersectRayWithDem( ray, dem, other );
    ASSERT_EQ( straight.hit(), chords.hit() ) << "ray " << i << ": " << straight.message << " / " << chords.message;
    if ( straight.hit() )
    {
      EXPECT_NEAR( straight.rangeM, chords.rangeM, 1e-3 ) << "ray " << i;
    }
  }
  std::filesystem::remove( path );
}

TEST( Dem, SmallHolesAreFilledLargeOnesReported )
{
  const auto holes = []( int c, int r ) { return ( c >= 100 && c < 103 && r >= 100 && r < 103 ) || ( c >= 300 && c < 360 && r >= 300 && r < 360 ); };
  const std::string path = projectedDem( holes, "holes" );
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const std::optional<double> filled = dem.heightAt( kX0 + 203.0, kY0 - 203.0 ); // centre of the small hole
  ASSERT_TRUE( filled.has_value() );
  EXPECT_NEAR( *filled, terrain( kX0 + 203.0, kY0 - 203.0 ), 1.0 );
  EXPECT_GE( dem.filledCellCount(), 9 );
  // The 60-cell hole is filled 16 cells in from each side; its middle stays empty.
  EXPECT_FALSE( dem.heightAt( kX0 + 660.0, kY0 - 660.0 ).has_value() );
  const DemIntersection hole = intersectRayWithDem( { { kX0 + 660.0, kY0 - 660.0, 900.0 }, { 0, 0, -1 } }, dem, same );
  EXPECT_EQ( hole.status, DemIntersection::Status::Hole ) << hole.message;
  // the message states the fill limit: 2 x 16 cells of 2 m
  EXPECT_NE( hole.message.find( "32 cells, 64 m" ), std::string::npos ) << hole.message;
  // batch outputs name each outcome
  EXPECT_EQ( demIntersectionStatusName( hole.status ), "dem_hole" );
  EXPECT_EQ( demIntersectionStatusName( DemIntersection::Status::Hit ), "ok" );
  EXPECT_EQ( demIntersectionStatusName( DemIntersection::Status::Miss ), "misses_dem" );
  EXPECT_EQ( demIntersectionStatusName( DemIntersection::Status::BelowSurface ), "below_dem" );
  // Filling does not depend on the tiling: small tiles give the same heights
  // everywhere around the large hole, tile borders included.
  DemOptions small;
  small.tileSize = 16;
  const Dem tiled( path, small );
  int compared = 0;
  for ( int r = 280; r < 380; ++r )
    for ( int c = 280; c < 380; ++c )
    {
      const double x = kX0 + 2.0 * c + 1.0, y = kY0 - 2.0 * r - 1.0;
      const std::optional<double> a = dem.heightAt( x, y ), b = tiled.heightAt( x, y );
      ASSERT_EQ( a.has_value(), b.has_value() ) << c << " " << r;
      if ( a )
      {
        EXPECT_EQ( *a, *b ) << c << " " << r;
        ++compared;
      }
    }
  EXPECT_GT( compared, 5000 );
  std::filesystem::remove( path );
}

TEST( Dem, UndeclaredNodataSentinelsAreHoles )
{
  // a plane with a 3 x 3 patch at float32's lowest value and no nodata declared for it (common in DEMs from
  // elsewhere): a hole, filled, not a pit 3.4e38 m deep (found by the dem fuzz target: rays hit nonsense there)
  const std::string path = ( std::filesystem::temp_directory_path() / "geostation-dem-sentinel.tif" ).string();
  const auto inPatch = []( double x, double y ) { return x > kX0 + 60.0 && x < kX0 + 66.0 && y < kY0 - 60.0 && y > kY0 - 66.0; };
  syntheticterrain::writeDem( path, "EPSG:32633", { kX0, 2.0, 0.0, kY0, 0.0, -2.0 }, 64, 64,
                              [&]( double x, double y ) { return inPatch( x, y ) ? -3.4028235e38 : 100.0 + 0.01 * ( x - kX0 ); } );
  const Dem dem( path );
  const std::optional<double> filled = dem.heightAt( kX0 + 63.0, kY0 - 63.0 );
  ASSERT_TRUE( filled.has_value() );
  EXPECT_NEAR( *filled, 100.63, 0.01 );
  EXPECT_GE( dem.filledCellCount(), 9 );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const DemIntersection hit = intersectRayWithDem( { { kX0 + 63.0, kY0 - 63.0, 150.0 }, { 0, 0, -1 } }, dem, same );
  ASSERT_TRUE( hit.hit() ) << hit.message;
  EXPECT_NEAR( hit.point.z(), 100.63, 0.01 );
  std::filesystem::remove( path );
}

TEST( DemIntersection, ACrossingJustBeforeTheEdgeIsFound )
{
  // A shallow ray that meets the terrain a few metres before the DEM ends.
  const std::string path = projectedDem( nullptr, "edge" );
  const Dem dem( path );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const double yEnd = kY0 - 1.0; // northernmost cell centres
  const Eigen::Vector3d target( kX0 + 500.0, yEnd - 3.0, 0.0 );
  const Eigen::Vector3d onSurface( target.x(), target.y(), *dem.heightAt( target.x(), target.y() ) );
  const Eigen::Vector3d start = onSurface + Eigen::Vector3d( 0.0, -400.0, 20.0 );
  const DemIntersection hit = intersectRayWithDem( { start, ( onSurface - start ).normalized() }, dem, same );
  const std::optional<double> expected = bruteForceRange( { start, ( onSurface - start ).normalized() }, dem, 420.0, 0.01 );
  ASSERT_TRUE( expected.has_value() );
  ASSERT_TRUE( hit.hit() ) << hit.message;
  EXPECT_NEAR( hit.rangeM, *expected, 0.01 );
  std::filesystem::remove( path );
}

TEST( Dem, TinyTilesAndCacheGiveTheSameAnswers )
{
  const std::string path = projectedDem();
  const Dem big( path );
  DemOptions tiny;
  tiny.tileSize = 16;
  tiny.cacheTiles = 9;
  const Dem small( path, tiny );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  std::mt19937 rng( 3 );
  std::uniform_real_distribution<double> azimuth( 0.0, 2 * M_PI ), pos( 100.0, 900.0 );
  for ( int i = 0; i < 40; ++i )
  {
    const double cx = kX0 + pos( rng ), cy = kY0 - pos( rng ), a = azimuth( rng );
    const Ray ray { { cx, cy, *big.heightAt( cx, cy ) + 30.0 }, Eigen::Vector3d( std::sin( a ), std::cos( a ), -0.2 ).normalized() };
    const DemIntersection p = intersectRayWithDem( ray, big, same ), q = intersectRayWithDem( ray, small, same );
    ASSERT_EQ( p.hit(), q.hit() ) << i << ": " << p.message << " / " << q.message << " ranges " << p.rangeM << " " << q.rangeM << " steps " << p.steps << " " << q.steps;
    if ( p.hit() )
    {
      EXPECT_NEAR( p.rangeM, q.rangeM, 2e-4 );
    }
  }
  std::filesystem::remove( path );
}

TEST( Dem, TilesWithoutHolesReadDirectlyGiveTheSameAnswers )
{
  // A Float32 DEM's tiles without holes are read straight into the tile, without the halo the fill needs; a
  // Float64 copy of the same heights takes the halo path for every tile. Heights, block maxima and crossings
  // must be equal to the bit - at the DEM's last, partial tiles and beside tiles with holes too.
  const auto holes = []( int c, int r ) { return ( c >= 70 && c < 74 && r >= 100 && r < 103 ) || ( c >= 300 && c < 360 && r >= 420 && r < 470 ) || ( c == 499 && r == 10 ); };
  const std::string path32 = tempPath( "dem-direct-32" ), path64 = tempPath( "dem-direct-64" );
  const std::array<double, 6> gt { kX0, 2.0, 0.0, kY0, 0.0, -2.0 };
  syntheticterrain::writeDem( path32, "EPSG:32633", gt, 500, 500, terrain, holes, GDT_Float32 );
  syntheticterrain::writeDem( path64, "EPSG:32633", gt, 500, 500, terrain, holes, GDT_Float64 );
  DemOptions options;
  options.tileSize = 64; // 500 = 7 x 64 + 52: partial tiles at the right and bottom
  options.cacheTiles = 9;
  const Dem direct( path32, options ), halo( path64, options );
  for ( int ty = 0; ty < 8; ++ty )
    for ( int tx = 0; tx < 8; ++tx )
    {
      Dem::TileView a, b;
      ASSERT_TRUE( direct.tileView( tx, ty, a ) );
      ASSERT_TRUE( halo.tileView( tx, ty, b ) );
      EXPECT_EQ( a.maxHeight, b.maxHeight ) << tx << " " << ty;
      for ( int k = 0; k < a.blocksPerSide * a.blocksPerSide; ++k )
        ASSERT_EQ( a.blockMax[k], b.blockMax[k] ) << tx << " " << ty << " block " << k;
      for ( int k = 0; k < a.stride * a.stride; ++k )
        ASSERT_TRUE( a.vertices[k] == b.vertices[k] || ( std::isnan( a.vertices[k] ) && std::isnan( b.vertices[k] ) ) ) << tx << " " << ty << " vertex " << k;
    }
  EXPECT_EQ( direct.filledCellCount(), halo.filledCellCount() );
  EXPECT_GT( direct.filledCellCount(), 0 );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  std::mt19937 rng( 12 );
  std::uniform_real_distribution<double> azimuth( 0.0, 2 * M_PI ), pos( 2.0, 998.0 );
  int hits = 0;
  for ( int i = 0; i < 300; ++i )
  {
    const double x = kX0 + pos( rng ), y = kY0 - pos( rng ), a = azimuth( rng );
    const std::optional<double> h = direct.heightAt( x, y );
    ASSERT_EQ( h.has_value(), halo.heightAt( x, y ).has_value() );
    if ( !h )
      continue;
    EXPECT_EQ( *h, *halo.heightAt( x, y ) );
    const Ray ray { { x, y, *h + 20.0 }, Eigen::Vector3d( std::sin( a ), std::cos( a ), -0.1 ).normalized() };
    const DemIntersection p = intersectRayWithDem( ray, direct, same ), q = intersectRayWithDem( ray, halo, same );
    ASSERT_EQ( p.hit(), q.hit() ) << i;
    hits += p.hit();
    if ( p.hit() )
    {
      EXPECT_EQ( p.rangeM, q.rangeM ) << i;
    }
  }
  EXPECT_GT( hits, 200 );
  std::filesystem::remove( path32 );
  std::filesystem::remove( path64 );
}

TEST( Dem, AGeographicDemServesAProjectedBlock )
{
  const CrsTransform toGeographic( "EPSG:32633", "EPSG:4326" );
  const std::string path = geographicDem( "geographic" );
  const Dem dem( path );
  EXPECT_TRUE( dem.isGeographic() );
  std::mt19937 rng( 4 );
  std::uniform_real_distribution<double> pos( 300.0, 700.0 ), azimuth( 0.0, 2 * M_PI ); // rays travel < 250 m: they stay over the DEM
  for ( int i = 0; i < 40; ++i )
  {
    const double x = kX0 + pos( rng ), y = kY0 - pos( rng ), a = azimuth( rng );
    const Ray ray { { x, y, 400.0 }, Eigen::Vector3d( std::sin( a ), std::cos( a ), -1.5 ).normalized() };
    const DemIntersection hit = intersectRayWithDem( ray, dem, toGeographic );
    ASSERT_TRUE( hit.hit() ) << hit.message;
    const Eigen::Vector3d lonLat = toGeographic.transform( hit.point );
    EXPECT_NEAR( hit.point.z(), *dem.heightAt( lonLat.x(), lonLat.y() ), 1e-3 );
    EXPECT_NEAR( hit.point.z(), terrain( hit.point.x(), hit.point.y() ), 0.1 ); // the sampled terrain
  }
  std::filesystem::remove( path );
}

TEST( DemIntersection, GrazingRaysOverAGeographicDemFindTheFirstCrossing )
{
  // Long, nearly level rays over a lon/lat grid: curved in the DEM's grid,
  // followed chord by chord; checked against brute force through PROJ.
  const CrsTransform toGeographic( "EPSG:32633", "EPSG:4326" );
  const std::string path = geographicDem( "geographic-grazing" );
  const Dem dem( path );
  const auto heightAbove = [&]( const Ray & ray, double t )
  {
    const Eigen::Vector3d p = ray.origin + t * ray.direction, q = toGeographic.transform( p );
    const std::optional<double> h = dem.heightAt( q.x(), q.y() );
    return h ? std::optional<double>( p.z() - *h ) : std::nullopt;
  };
  std::mt19937 rng( 9 );
  std::uniform_real_distribution<double> pos( 300.0, 700.0 ), azimuth( 0.0, 2 * M_PI ), dip( 0.5, 4.0 );
  int hits = 0;
  for ( int i = 0; i < 15; ++i )
  {
    const double x = kX0 + pos( rng ), y = kY0 - pos( rng ), a = azimuth( rng ), down = dip( rng ) * M_PI / 180.0;
    const Eigen::Vector3d lonLat = toGeographic.transform( { x, y, 0.0 } );
    const Ray ray { { x, y, *dem.heightAt( lonLat.x(), lonLat.y() ) + 1.7 }, Eigen::Vector3d( std::sin( a ) * std::cos( down ), std::cos( a ) * std::cos( down ), -std::sin( down ) ) };
    std::optional<double> expected;
    double previous = 0.0;
    for ( double t = 0.0; t < 1500.0; t += 0.05 )
    {
      const std::optional<double> h = heightAbove( ray, t );
      if ( !h )
        break;
      if ( *h <= 0.0 )
      {
        double lo = previous, hi = t;
        for ( int k = 0; k < 40; ++k )
          ( *heightAbove( ray, 0.5 * ( lo + hi ) ) > 0.0 ? lo : hi ) = 0.5 * ( lo + hi );
        expected = 0.5 * ( lo + hi );
        break;
      }
      previous = t;
    }
    const DemIntersection hit = intersectRayWithDem( ray, dem, toGeographic );
    ASSERT_EQ( hit.hit(), expected.has_value() ) << "ray " << i << ": " << hit.message;
    if ( !expected )
      continue;
    ++hits;
    EXPECT_NEAR( hit.rangeM, *expected, 0.005 ) << "ray " << i;
    EXPECT_NEAR( *heightAbove( ray, hit.rangeM ), 0.0, 1e-3 ) << "ray " << i;
  }
  EXPECT_GT( hits, 8 );
  std::filesystem::remove( path );
}

TEST( Dem, ADemWithoutCrsIsRefused )
{
  const std::string path = writeDem( "nocrs", nullptr, { kX0, 2.0, 0.0, kY0, 0.0, -2.0 }, 20, 20, terrain );
  try
  {
    Dem dem( path );
    FAIL() << "a DEM without CRS was accepted";
  }
  catch ( const std::runtime_error &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "has no CRS" ), std::string::npos ) << e.what();
  }
  std::filesystem::remove( path );
}

TEST( Dem, LargerHolesAreBridgedWithASigma )
{
  // a 60-cell hole (too large to fill) and a 200-cell one (larger than the bridge, 100 cells); tiles of 64
  // cells, so both span tile borders
  const auto holes = []( int c, int r ) { return ( c >= 300 && c < 360 && r >= 300 && r < 360 ) || ( c >= 40 && c < 240 && r >= 40 && r < 240 ); };
  const auto plane = []( double x, double y ) { return 200.0 + 0.05 * ( x - kX0 ) - 0.03 * ( kY0 - y ); };
  const std::string planePath = writeDem( "bridge-plane", "EPSG:32633", { kX0, 2.0, 0.0, kY0, 0.0, -2.0 }, 500, 500, plane, holes );
  DemOptions options;
  options.tileSize = 64;
  options.bridgeHolesUpToCells = 100;
  const Dem dem( planePath, options );
  const CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const double cx = kX0 + 660.0, cy = kY0 - 660.0; // the 60-cell hole's centre
  // a plane is bridged exactly; the sigma grows from the rim, 5 cm per metre
  ASSERT_TRUE( dem.heightAt( cx, cy ).has_value() );
  EXPECT_NEAR( *dem.heightAt( cx, cy ), plane( cx, cy ), 1e-3 );
  const std::optional<double> sigmaCentre = dem.bridgeSigmaAt( cx, cy );
  ASSERT_TRUE( sigmaCentre.has_value() );
  // (the whole hole is bridged from the data at its rims, the fill's rings too: the centre is 60 m from them)
  EXPECT_GT( *sigmaCentre, 0.05 * 58.0 );
  EXPECT_LT( *sigmaCentre, 0.05 * 62.0 );
  EXPECT_EQ( dem.bridgeSigmaAt( kX0 + 900.0, kY0 - 400.0 ).value_or( -1.0 ), 0.0 ); // no hole there
  EXPECT_GT( dem.bridgedCellCount(), 0 );
  const DemIntersection down = intersectRayWithDem( { { cx, cy, 900.0 }, { 0, 0, -1 } }, dem, same );
  ASSERT_EQ( down.status, DemIntersection::Status::Hit ) << down.message;
  EXPECT_NEAR( down.point.z(), plane( cx, cy ), 1e-3 );
  // the larger hole stays a hole, and the message says up to what it is bridged
  EXPECT_FALSE( dem.heightAt( kX0 + 280.0, kY0 - 280.0 ).has_value() );
  const DemIntersection hole = intersectRayWithDem( { { kX0 + 280.0, kY0 - 280.0, 900.0 }, { 0, 0, -1 } }, dem, same );
  EXPECT_EQ( hole.status, DemIntersection::Status::Hole );
  EXPECT_NE( hole.message.find( "100 cells, 200 m, across are bridged" ), std::string::npos ) << hole.message;
  // without bridging the 60-cell hole's middle is empty
  EXPECT_FALSE( Dem( planePath ).heightAt( cx, cy ).has_value() );

  // terrain with relief: the bridged heights' errors against their sigmas, and the same with other tiles
  const std::string terrainPath = writeDem( "bridge-terrain", "EPSG:32633", { kX0, 2.0, 0.0, kY0, 0.0, -2.0 }, 500, 500, terrain, holes );
  const Dem rough( terrainPath, options );
  DemOptions bigTiles = options;
  bigTiles.tileSize = 256;
  const Dem rough256( terrainPath, bigTiles );
  int bridged = 0, within = 0;
  double worst = 0.0, sumW2 = 0.0;
  for ( int r = 300; r < 360; ++r )
    for ( int c = 300; c < 360; ++c )
    {
      const double x = kX0 + 2.0 * c + 1.0, y = kY0 - 2.0 * r - 1.0;
      const std::optional<double> h = rough.heightAt( x, y ), sigma = rough.bridgeSigmaAt( x, y );
      ASSERT_TRUE( h && sigma ) << c << " " << r;
      ASSERT_EQ( *h, *rough256.heightAt( x, y ) ) << "the bridge does not depend on the tiling, " << c << " " << r;
      ASSERT_EQ( *sigma, *rough256.bridgeSigmaAt( x, y ) ) << c << " " << r;
      if ( *sigma <= 0.0 )
        continue; // filled, not bridged
      ++bridged;
      const double w = std::abs( *h - terrain( x, y ) ) / *sigma;
      worst = std::max( worst, w );
      within += w <= 2.0 ? 1 : 0;
      sumW2 += w * w;
    }
  const double rmsW = std::sqrt( sumW2 / std::max( 1, bridged ) );
  std::printf( "bridged cells %d, within 2 sigma %.1f %%, worst %.2f sigma, RMS %.2f sigma\n", bridged, 100.0 * within / std::max( 1, bridged ), worst, rmsW );
  EXPECT_GT( bridged, 3000 );
  EXPECT_GE( within, 0.9 * bridged ) << "the bridge's sigma is not optimistic";
  EXPECT_GT( rmsW, 0.15 ) << "nor useless";
  std::filesystem::remove( planePath );
  std::filesystem::remove( terrainPath );
}
