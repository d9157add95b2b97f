// How much of the ground seen in a photo the DEM covers (issue 18: a DEM
// layer that does not reach the photo's footprint is said so, not found
// out one refused vertex at a time). The synthetic terrain (800 m square,
// 2 m cells) under a nadir camera whose footprint is about 500 x 375 m.
#include <cmath>
#include <filesystem>
#include <optional>

#include <gtest/gtest.h>

#include "dem/demcoverage.h"
#include "geometry/crs.h"
#include "pinholecamera.h"
#include "syntheticterrain.h"

using namespace geostation;
using namespace syntheticterrain;

namespace
{
  Camera frameCamera() { return centredPinhole( "frame", 1000, 750, 1000.0 ); }

  ExteriorOrientation at( double x, double y, double z, double omegaDeg = 0.0 )
  {
    ExteriorOrientation eo;
    eo.projectionCentre = Eigen::Vector3d( x, y, z );
    eo.omegaDeg = omegaDeg;
    return eo;
  }

  //! `nominalFromScan`: a scanned film's scan affine (none: a digital photo).
  DemCoverageSummary coverage( const std::string &demPath, const ExteriorOrientation &eo, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromScan = std::nullopt )
  {
    const Dem dem( demPath );
    const CrsTransform same( "EPSG:32633", dem.crsWkt() );
    OrientedImage image( frameCamera(), eo );
    if ( nominalFromScan )
      image.setScanAffine( *nominalFromScan );
    const Monoplotter mono( image, dem, same );
    return demCoverageOfImage( mono );
  }
} // namespace

TEST( DemCoverage, WholePartlyAndNotAtAll )
{
  const std::string path = tempPath( "demcoverage" );
  writeTerrain( path, 400 );
  const double xMid = kX0 + 400.0, yMid = kY0 - 400.0;

  const DemCoverageSummary whole = coverage( path, at( xMid, yMid, 620.0 ) );
  EXPECT_EQ( whole.samples, 108 );
  EXPECT_EQ( whole.sky, 0 );
  EXPECT_TRUE( whole.complete() ) << whole.message;
  EXPECT_NE( whole.message.find( "covers the ground of the whole photo" ), std::string::npos ) << whole.message;

  // over the DEM's east edge: the right half of the footprint is off it
  const DemCoverageSummary half = coverage( path, at( kX0 + 800.0, yMid, 620.0 ) );
  EXPECT_FALSE( half.complete() );
  EXPECT_NEAR( half.coveredFraction(), 0.5, 0.09 ) << half.message;
  EXPECT_GT( half.uncoveredCentrePx.x(), 2.0 * 1000 / 3.0 );
  EXPECT_NEAR( half.uncoveredCentrePx.y(), 375.0, 1.0 );
  EXPECT_EQ( half.onHoles, 0 );
  EXPECT_NE( half.message.find( "mostly in the right side of the frame" ), std::string::npos ) << half.message;

  // the same photo as a scan whose picture lies 300 px right and 200 px down in the file, scaled by 1.001 and
  // turned a little: sampled over the picture, not over the scan's first 1000 x 750 pixels
  Eigen::Matrix<double, 2, 3> nominalFromScan;
  const double a = 0.2 * M_PI / 180.0, k = 1.0 / 1.001;
  nominalFromScan << k * std::cos( a ), k * std::sin( a ), 0.0, -k * std::sin( a ), k * std::cos( a ), 0.0;
  nominalFromScan.col( 2 ) = -nominalFromScan.leftCols<2>() * Eigen::Vector2d( 300.0, 200.0 );
  const DemCoverageSummary scanned = coverage( path, at( kX0 + 800.0, yMid, 620.0 ), nominalFromScan );
  EXPECT_EQ( scanned.onDem, half.onDem ) << scanned.message;
  EXPECT_EQ( scanned.offDem, half.offDem );
  EXPECT_EQ( scanned.message, half.message );
  EXPECT_NEAR( scanned.uncoveredCentrePx.x(), half.uncoveredCentrePx.x() + 300.0, 3.0 );
  EXPECT_NEAR( scanned.uncoveredCentrePx.y(), half.uncoveredCentrePx.y() + 200.0, 3.0 );

  // over the south-west corner: the DEM is in the top right quarter of the photo
  const DemCoverageSummary corner = coverage( path, at( kX0, kY0 - 800.0, 620.0 ) );
  EXPECT_NEAR( corner.coveredFraction(), 0.25, 0.09 ) << corner.message;
  EXPECT_GT( corner.coveredCentrePx.x(), 2.0 * 1000 / 3.0 );
  EXPECT_LT( corner.coveredCentrePx.y(), 750 / 3.0 );
  EXPECT_NE( corner.message.find( "covers only 22 % of the ground seen in the photo, in the top right of the frame" ), std::string::npos ) << corner.message;

  // another area altogether
  const DemCoverageSummary none = coverage( path, at( kX0 + 5000.0, yMid, 620.0 ) );
  EXPECT_EQ( none.onDem, 0 );
  EXPECT_EQ( none.offDem, 108 );
  EXPECT_NE( none.message.find( "does not cover the ground seen in the photo" ), std::string::npos ) << none.message;
  std::filesystem::remove( path );
}

TEST( DemCoverage, HolesAndSkyAreToldApart )
{
  // a hole 200 m across in the middle, far beyond what is filled (about 32 cells)
  const std::string path = tempPath( "demcoverage-hole" );
  writeTerrain( path, 400, kX0, "EPSG:32633", 0.05, []( int c, int r ) { return c >= 150 && c < 250 && r >= 150 && r < 250; } );
  const DemCoverageSummary hole = coverage( path, at( kX0 + 400.0, kY0 - 400.0, 620.0 ) );
  EXPECT_GT( hole.onHoles, 10 ) << hole.message;
  EXPECT_EQ( hole.offDem, 0 );
  EXPECT_NEAR( hole.uncoveredCentrePx.x(), 500.0, 1.0 );
  EXPECT_NE( hole.message.find( "on holes in it), mostly in the middle" ), std::string::npos ) << hole.message;

  // looking north, 2 degrees up: the rays of the five rows down to 2 degrees below the axis (row 410) point
  // at or above the horizon
  const DemCoverageSummary level = coverage( path, at( kX0 + 400.0, kY0 - 700.0, 150.0, 92.0 ) );
  EXPECT_EQ( level.sky, 5 * 12 );
  EXPECT_EQ( level.groundSamples(), 4 * 12 );
  EXPECT_GT( level.onDem, 0 );

  // looking up: no ground at all
  const DemCoverageSummary up = coverage( path, at( kX0 + 400.0, kY0 - 400.0, 150.0, 180.0 ) );
  EXPECT_EQ( up.sky, 108 );
  EXPECT_NE( up.message.find( "no part of the photo looks down at the ground" ), std::string::npos ) << up.message;

  EXPECT_THROW( DemCoverageOptions( { 1, 9 } ).check(), std::invalid_argument );
  std::filesystem::remove( path );
}
