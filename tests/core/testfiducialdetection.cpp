// Automatic fiducial detection on synthetic scans with known mark positions.
#include <filesystem>
#include <functional>
#include <random>

#include <Eigen/Dense>

#include <gdal.h>
#include <gtest/gtest.h>

#include "adjustment/innerorientation.h"
#include "geometry/rotation.h"
#include "imageproc/fiducialdetection.h"

using namespace geostation;

namespace
{
  constexpr int kSize = 4096;
  constexpr double kScanMm = 0.05;

  std::vector<Fiducial> cornerFiducials()
  {
    return { { "F1", { -95.0, 95.0 } }, { "F2", { 95.0, 95.0 } }, { "F3", { 95.0, -95.0 } }, { "F4", { -95.0, -95.0 } }, { "F5", { 0.0, 100.0 } } };
  }

  //! Scan affine: photo mm -> pixel, rotated 0.5 deg with 0.2 % affinity.
  Eigen::Vector2d pixelOf( const Eigen::Vector2d &photoMm )
  {
    const double b = degToRad( 0.5 );
    Eigen::Matrix2d a; // on (u, v) = (col, -row): photo = a (uv - uv0)
    a << std::cos( b ), std::sin( b ), -std::sin( b ), std::cos( b );
    a = a * Eigen::DiagonalMatrix<double, 2>( kScanMm * 1.002, kScanMm );
    const Eigen::Vector2d uv = Eigen::Vector2d( 2048.0, -2048.0 ) + a.inverse() * photoMm;
    return { uv.x(), -uv.y() };
  }

  //! Renders marks (coverage function around each centre) on a noisy background and writes a GeoTIFF.
  std::string renderScan( const std::string &name, const std::function<double( double, double )> &coverage, int radius, std::mt19937 &rng )
  {
    std::vector<unsigned char> pixels( static_cast<size_t>( kSize ) * kSize );
    std::normal_distribution<double> noise( 60.0, 4.0 );
    for ( unsigned char &p : pixels )
      p = static_cast<unsigned char>( std::clamp( noise( rng ), 0.0, 255.0 ) );
    for ( const Fiducial &f : cornerFiducials() )
    {
      const Eigen::Vector2d c = pixelOf( f.photoMm );
      for ( int y = static_cast<int>( c.y() ) - radius; y <= static_cast<int>( c.y() ) + radius; ++y )
        for ( int x = static_cast<int>( c.x() ) - radius; x <= static_cast<int>( c.x() ) + radius; ++x )
        {
          // 16 x 16 supersampling: straight edges are placed to 1/16 px
          // (coarser sampling shifts thin marks by up to half a sample step).
          double cover = 0.0;
          for ( int sy = 0; sy < 16; ++sy )
            for ( int sx = 0; sx < 16; ++sx )
              cover += coverage( x + ( sx + 0.5 ) / 16 - c.x(), y + ( sy + 0.5 ) / 16 - c.y() ) / 256.0;
          unsigned char &p = pixels[static_cast<size_t>( y ) * kSize + x];
          p = static_cast<unsigned char>( std::clamp( p + cover * 150.0, 0.0, 255.0 ) );
        }
    }
    const std::string path = ( std::filesystem::temp_directory_path() / ( name + std::to_string( ::getpid() ) + ".tif" ) ).string();
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.c_str(), kSize, kSize, 1, GDT_Byte, nullptr );
    EXPECT_EQ( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, 0, kSize, kSize, pixels.data(), kSize, kSize, GDT_Byte, 0, 0 ), CE_None );
    GDALClose( ds );
    return path;
  }

  void expectFound( const std::array<DetectedFiducial, 4> &found, double tolerancePx )
  {
    const std::array<std::string, 4> ids = cornerFiducialIds( cornerFiducials() );
    EXPECT_EQ( ids, ( std::array<std::string, 4> { "F1", "F2", "F3", "F4" } ) );
    for ( int k = 0; k < 4; ++k )
    {
      ASSERT_TRUE( found[k].found() ) << k << ": " << found[k].message;
      const Fiducial f = cornerFiducials()[k];
      EXPECT_LT( ( found[k].pixelInImage - pixelOf( f.photoMm ) ).norm(), tolerancePx ) << f.id << " found at " << found[k].pixelInImage.transpose() << " true " << pixelOf( f.photoMm ).transpose();
      EXPECT_GT( found[k].score, 0.7 );
    }
  }
} // namespace

TEST( FiducialDetection, GenericDiscsAreLocatedToAFractionOfAPixel )
{
  std::mt19937 rng( 1 );
  const std::string path = renderScan( "geostation-discs-", []( double x, double y ) { return std::hypot( x, y ) <= 12.0 ? 1.0 : 0.0; }, 16, rng );
  FiducialDetectionOptions options;
  options.scanPixelMm = kScanMm;
  options.markDiameterPx = 24.0;
  const std::array<DetectedFiducial, 4> found = detectCornerFiducials( path, options );
  expectFound( found, 0.03 );

  // The detections give the scan's inner orientation.
  std::vector<FiducialMeasurement> measured;
  const std::array<std::string, 4> ids = cornerFiducialIds( cornerFiducials() );
  for ( int k = 0; k < 4; ++k )
    measured.push_back( { ids[k], found[k].pixelInImage } );
  const InnerOrientationSummary io = innerOrientation( cornerFiducials(), measured );
  ASSERT_TRUE( io.ok() ) << io.message;
  EXPECT_NEAR( io.decomposition.betaDeg, 0.5, 0.002 );
  EXPECT_NEAR( io.decomposition.affinityPct, 0.2, 0.01 );
  EXPECT_LT( io.rmsResidualMm, 0.05 * kScanMm );
  std::filesystem::remove( path );
}

TEST( FiducialDetection, AUserTemplateFindsCrossMarks )
{
  const auto cross = []( double x, double y ) { return ( std::abs( x ) <= 2.5 && std::abs( y ) <= 20.0 ) || ( std::abs( y ) <= 2.5 && std::abs( x ) <= 20.0 ) ? 1.0 : 0.0; };
  std::mt19937 rng( 2 );
  const std::string path = renderScan( "geostation-crosses-", cross, 22, rng );
  cv::Mat markTemplate( 49, 49, CV_8U, cv::Scalar( 60 ) );
  for ( int y = 0; y < 49; ++y )
    for ( int x = 0; x < 49; ++x )
      markTemplate.at<unsigned char>( y, x ) = cross( x + 0.5 - 24.5, y + 0.5 - 24.5 ) > 0 ? 210 : 60;
  FiducialDetectionOptions options;
  options.scanPixelMm = kScanMm;
  options.markTemplate = markTemplate;
  expectFound( detectCornerFiducials( path, options ), 0.08 );

  // A disc template does not take a cross for a disc: no strong match.
  FiducialDetectionOptions wrong;
  wrong.scanPixelMm = kScanMm;
  wrong.markDiameterPx = 60.0;
  wrong.minScore = 0.9;
  const std::array<DetectedFiducial, 4> none = detectCornerFiducials( path, wrong );
  for ( const DetectedFiducial &d : none )
  {
    EXPECT_FALSE( d.found() );
    EXPECT_EQ( d.status, DetectedFiducial::Status::NoMark );
    EXPECT_NE( d.message.find( "no mark" ), std::string::npos );
  }
  std::filesystem::remove( path );
}

TEST( FiducialDetection, AStopLeavesTheCornersNotLookedForCancelled )
{
  // the orientation dock's Cancel: told before each corner; once asked to stop, the corners left are not read
  std::mt19937 rng( 1 );
  const std::string path = renderScan( "geostation-discs-stop-", []( double x, double y ) { return std::hypot( x, y ) <= 12.0 ? 1.0 : 0.0; }, 16, rng );
  FiducialDetectionOptions options;
  options.scanPixelMm = kScanMm;
  options.markDiameterPx = 24.0;
  int told = 0;
  std::vector<std::string> stages;
  options.progress = Progress( [&]( double, const std::string &stage ) { ++told; stages.push_back( stage ); }, [&] { return told >= 3; } ); // asked to stop when told of the third corner
  const std::array<DetectedFiducial, 4> found = detectCornerFiducials( path, options );
  EXPECT_TRUE( found[0].found() );
  EXPECT_TRUE( found[1].found() );
  EXPECT_EQ( found[2].status, DetectedFiducial::Status::Cancelled );
  EXPECT_EQ( found[3].status, DetectedFiducial::Status::Cancelled );
  EXPECT_EQ( stages.front(), "corner 1 of 4" );
  std::filesystem::remove( path );
}

TEST( FiducialDetection, BadInputThrows )
{
  FiducialDetectionOptions options;
  EXPECT_THROW( detectCornerFiducials( "/nonexistent.tif", options ), std::invalid_argument );
  options.scanPixelMm = 0.05;
  EXPECT_THROW( detectCornerFiducials( "/nonexistent.tif", options ), std::runtime_error );
}
