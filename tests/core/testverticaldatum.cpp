// Heights and vertical datums: a van's GNSS heights (ellipsoidal, above
// WGS 84) imported into a block CRS with a vertical datum become heights
// above the geoid - checked against the EGM96 grid read on its own with
// GDAL - and a vertical datum whose geoid model is not installed is refused
// with one sentence instead of passing the heights through unchanged.
#include <cmath>
#include <fstream>

#include <gdal.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "rigcameras.h"
#include "testfiles.h"

#include "geometry/crs.h"
#include "io/trajectoryimport.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  const char *kEgm96Grid = "/usr/share/proj/egm96_15.gtx"; // Debian's proj-data, which PROJ depends on

  //! The EGM96 geoid undulation (m) at a longitude and latitude: bilinear between the grid's nodes, read with GDAL.
  double undulationFromGrid( double lonDeg, double latDeg )
  {
    GDALAllRegister();
    GDALDatasetH grid = GDALOpen( kEgm96Grid, GA_ReadOnly );
    EXPECT_NE( grid, nullptr );
    if ( !grid )
      return std::nan( "" );
    double gt[6];
    GDALGetGeoTransform( grid, gt );
    // node (i, j) at the centre of GDAL's pixel (i, j)
    double col = ( lonDeg - gt[0] ) / gt[1] - 0.5, row = ( latDeg - gt[3] ) / gt[5] - 0.5;
    const int width = GDALGetRasterXSize( grid );
    if ( col < 0 )
      col += 360.0 / gt[1];
    if ( col > width - 1 )
      col -= 360.0 / gt[1];
    const int c0 = static_cast<int>( std::floor( col ) ), r0 = static_cast<int>( std::floor( row ) );
    float v[4];
    EXPECT_EQ( GDALRasterIO( GDALGetRasterBand( grid, 1 ), GF_Read, c0, r0, 2, 2, v, 2, 2, GDT_Float32, 0, 0 ), CE_None );
    GDALClose( grid );
    const double fc = col - c0, fr = row - r0;
    return ( 1 - fr ) * ( ( 1 - fc ) * v[0] + fc * v[1] ) + fr * ( ( 1 - fc ) * v[2] + fc * v[3] );
  }

  BlockImportSummary importRows( const fs::path &dir, const std::string &rows, const std::string &crs )
  {
    std::ofstream( dir / "trajectory.csv" ) << "station,latitude,longitude,height,roll,pitch,heading\n" << rows;
    TrajectoryImportOptions options;
    options.crs = crs;
    options.requireImageFiles = false;
    return importTrajectory( { geostation::testing::forwardRigCamera( "img/{station}.png" ) }, dir / "trajectory.csv", options );
  }
} // namespace

TEST( VerticalDatum, EllipsoidalHeightsBecomeHeightsAboveTheGeoid )
{
  const fs::path dir = freshTestFolder( "vertical-datum" );
  // two stations 300 km apart in UTM 17: the geoid lies 33-34 m below the ellipsoid there, differently at each
  const std::string rows = "P1,40.0,-78.0,200.0,0,0,0\nP2,42.5,-80.25,180.0,0,0,90\n";
  const BlockImportSummary ellipsoidal = importRows( dir, rows, "EPSG:32617" );
  const BlockImportSummary aboveGeoid = importRows( dir, rows, "EPSG:32617+5773" );
  ASSERT_EQ( ellipsoidal.block.images.size(), 2u );
  ASSERT_EQ( aboveGeoid.block.images.size(), 2u );
  const double lon[2] = { -78.0, -80.25 }, lat[2] = { 40.0, 42.5 }, h[2] = { 200.0, 180.0 };
  for ( int i = 0; i < 2; ++i )
  {
    const Eigen::Vector3d a = ellipsoidal.block.images[i].exterior->projectionCentre, b = aboveGeoid.block.images[i].exterior->projectionCentre;
    const double n = undulationFromGrid( lon[i], lat[i] );
    EXPECT_LT( n, -30.0 );
    EXPECT_NEAR( a.z(), h[i], 1e-9 );                          // a CRS without a vertical datum: heights as given
    EXPECT_NEAR( b.z(), h[i] - n, 0.01 ) << "station " << i;   // H = h - N
    EXPECT_NEAR( ( a - b ).head<2>().norm(), 0.0, 1e-6 );      // the plan position is the same
  }
  EXPECT_NE( std::find( aboveGeoid.converted.begin(), aboveGeoid.converted.end(), "ellipsoidal heights above WGS 84 became EGM96 heights through its geoid model" ),
             aboveGeoid.converted.end() );
  bool toldEllipsoidal = false;
  for ( const std::string &s : ellipsoidal.converted )
    toldEllipsoidal = toldEllipsoidal || s.find( "heights kept as given: ellipsoidal heights above WGS 84" ) != std::string::npos;
  EXPECT_TRUE( toldEllipsoidal );
  fs::remove_all( dir );
}

TEST( VerticalDatum, AGeoidModelThatIsNotInstalledIsRefused )
{
  // DHHN2016 needs the GCG2016 quasigeoid grid, which Debian's proj-data does not ship
  const fs::path dir = freshTestFolder( "vertical-datum-missing" );
  const std::string e = errorOf( [&] { importRows( dir, "P1,50.0,9.0,200.0,0,0,0\n", "EPSG:25832+7837" ); } );
  EXPECT_NE( e.find( "heights cannot be brought into DHHN2016 height" ), std::string::npos ) << e;
  EXPECT_NE( e.find( "geoid model it needs is not installed" ), std::string::npos ) << e;
  // from a 2-D CRS nothing is claimed about heights: they pass through
  EXPECT_NO_THROW( CrsTransform( "EPSG:4326", "EPSG:25832+7837" ) );
  EXPECT_EQ( verticalCrsName( "EPSG:25832" ), "" );
  EXPECT_EQ( verticalCrsName( "EPSG:25832+7837" ), "DHHN2016 height" );
  fs::remove_all( dir );
}
