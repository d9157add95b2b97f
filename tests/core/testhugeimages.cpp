// Images too large to prepare whole for matching: a pair of 20 000 x 20 000
// aerial frames (generated as sparse GeoTIFFs, a real photograph's texture
// where the point is) measured through the match cache's windows. The
// measurement must find the conjugate point the orientation says, holding
// only the windows measurementWindows() names (megabytes, not the 3.6 GB a
// whole prepared frame takes).
#include <cstdio>
#include <filesystem>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

#include <gdal.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "geometry/projection.h"
#include "workstation/matchimagecache.h"
#include "workstation/measurementwindows.h"
#include "workstation/pointmeasurer.h"

using namespace geostation;

namespace
{
  constexpr int kSize = 20000;

  //! A nadir frame camera of 20 000 x 20 000 pixels, f = 20 000 px.
  OrientedImage nadirImage( const Eigen::Vector3d &centre )
  {
    Camera camera;
    camera.id = "huge";
    camera.width = camera.height = kSize;
    camera.f = 20000.0;
    camera.cx = camera.cy = kSize / 2.0;
    ExteriorOrientation eo;
    eo.projectionCentre = centre;
    return OrientedImage( camera, eo );
  }

  /**
   * A sparse, tiled 20 000 x 20 000 GeoTIFF, zero except for `patch` with
   * its top-left pixel at `at` (only the patch's tiles are written).
   */
  void writeSparse( const std::string &path, const cv::Mat &patch, const cv::Point &at )
  {
    GDALAllRegister();
    const char *options[] = { "TILED=YES", "SPARSE_OK=TRUE", "COMPRESS=DEFLATE", nullptr };
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.c_str(), kSize, kSize, 1, GDT_Byte, const_cast<char **>( options ) );
    ASSERT_NE( ds, nullptr );
    ASSERT_EQ( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, at.x, at.y, patch.cols, patch.rows, const_cast<uchar *>( patch.data ), patch.cols, patch.rows,
                             GDT_Byte, 0, static_cast<int>( patch.step[0] ) ),
               CE_None );
    GDALClose( ds );
  }

  long peakResidentMb()
  {
    rusage usage {};
    getrusage( RUSAGE_SELF, &usage );
    return usage.ru_maxrss / 1024;
  }
}

TEST( HugeImages, APointMeasuredInWindowsOfTwentyThousandPixelFrames )
{
  const cv::Mat photo = cv::imread( "/usr/share/doc/opencv-doc/examples/data/aero1.jpg", cv::IMREAD_GRAYSCALE );
  ASSERT_FALSE( photo.empty() ) << "aero1.jpg (Debian package opencv-doc)";
  // two frames 500 m above flat ground, 100 m apart: the ground moves 4000 px between them
  const OrientedImage left = nadirImage( Eigen::Vector3d( 0, 0, 500 ) ), right = nadirImage( Eigen::Vector3d( 100, 0, 500 ) );
  const Eigen::Vector3d ground( 130.0, -40.0, 0.0 );
  const Eigen::Vector2d inLeft = left.projectGroundToPixel( ground ).pixelInImage, inRight = right.projectGroundToPixel( ground ).pixelInImage;
  const Eigen::Vector2d shift = inRight - inLeft;
  ASSERT_NEAR( shift.x(), std::round( shift.x() ), 1e-6 );
  ASSERT_NEAR( shift.y(), std::round( shift.y() ), 1e-6 );
  // the photograph's texture on the ground around the point, in both frames
  const cv::Mat patch = photo( cv::Rect( 100, 50, 400, 400 ) );
  const cv::Point atLeft( static_cast<int>( inLeft.x() ) - 200, static_cast<int>( inLeft.y() ) - 200 );
  const cv::Point atRight = atLeft + cv::Point( static_cast<int>( std::round( shift.x() ) ), static_cast<int>( std::round( shift.y() ) ) );
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-huge-" + std::to_string( ::getpid() ) );
  std::filesystem::create_directories( dir );
  writeSparse( ( dir / "left.tif" ).string(), patch, atLeft );
  writeSparse( ( dir / "right.tif" ).string(), patch, atRight );
  EXPECT_LT( std::filesystem::file_size( dir / "left.tif" ), 2'000'000u ) << "sparse";

  MatchImageCache cache;
  std::vector<MeasurementView> views { { "left", &left, nullptr }, { "right", &right, nullptr } };
  const std::string paths[2] = { ( dir / "left.tif" ).string(), ( dir / "right.tif" ).string() };
  std::vector<cv::Size> sizes;
  for ( const std::string &path : paths )
  {
    const MatchImageCache::Entry entry = cache.get( path );
    EXPECT_TRUE( entry.ok() ) << entry.message;
    EXPECT_TRUE( entry.needsWindow );
    EXPECT_EQ( entry.image, nullptr );
    sizes.push_back( entry.imageSize );
  }
  EXPECT_EQ( sizes[0], cv::Size( kSize, kSize ) );
  EXPECT_EQ( cache.bytes(), 0u ) << "nothing is prepared before a window is asked for";

  ProposalOptions options;
  options.epipolar = EpipolarOptions { 100.0, 2000.0, 2.0, 20000 }; // 100 m to 2 km below the camera
  options.area.windowWidth = options.area.windowHeight = 21;
  options.area.lsm = true;
  options.area.lsmOptions.windowWidth = options.area.lsmOptions.windowHeight = 21;
  const Eigen::Vector2d click = inLeft + Eigen::Vector2d( 17.3, -11.6 ); // on the texture, off the patch's centre
  const Eigen::Vector2d truth = click + shift;
  const auto measure = [&]( long long maxPixels, MeasurementWindowSummary &windows )
  {
    windows = measurementWindows( views, sizes, 0, click, options, maxPixels );
    std::vector<std::shared_ptr<const MatchImage>> held;
    for ( size_t i = 0; i < views.size(); ++i )
    {
      if ( !windows.windows[i] )
        continue;
      const MatchImageCache::Entry entry = cache.get( paths[i], *windows.windows[i] );
      EXPECT_TRUE( entry.ok() ) << entry.message;
      held.push_back( entry.image );
      views[i].pixels = entry.image.get();
    }
    return proposeConjugates( views, 0, click, options );
  };

  // the whole curve from 100 m to 2 km fits one window of the right frame
  MeasurementWindowSummary windows;
  std::vector<ConjugateProposal> proposals = measure( cache.maxWholePixels(), windows );
  ASSERT_TRUE( windows.windows[0] && windows.windows[1] );
  EXPECT_TRUE( windows.cut.empty() );
  std::printf( "windows: left %d x %d, right %d x %d px; %.1f MB prepared (a whole frame: %.0f MB)\n", windows.windows[0]->width, windows.windows[0]->height,
               windows.windows[1]->width, windows.windows[1]->height, cache.bytes() / 1e6, 9.0 * kSize * kSize / 1e6 );
  EXPECT_GT( windows.windows[1]->width, 10000 ) << "the curve runs across the frame";
  ASSERT_TRUE( proposals[1].matched() ) << proposals[1].message;
  EXPECT_EQ( proposals[1].status, MatchStatus::Lsm );
  EXPECT_LT( ( proposals[1].pixelInImage - truth ).norm(), 0.05 ) << proposals[1].pixelInImage.transpose() << " truth " << truth.transpose();
  EXPECT_LT( cache.bytes(), 40'000'000u );
  // a window within the one kept is served from it
  const size_t before = cache.bytes();
  const cv::Rect inside( windows.windows[1]->x + 100, windows.windows[1]->y + 10, 200, 100 );
  EXPECT_EQ( cache.get( paths[1], inside ).image.get(), views[1].pixels );
  EXPECT_EQ( cache.bytes(), before );

  // with less room the right frame's window keeps the curve around the ground's prediction, and still finds the point
  options.groundOfPixel = []( const OrientedImage &image, const Eigen::Vector2d &pixel ) -> std::optional<Eigen::Vector3d>
  {
    const std::optional<Ray> ray = image.worldRayFromPixel( pixel );
    if ( !ray || std::abs( ray->direction.z() ) < 1e-9 )
      return std::nullopt;
    return ray->origin + ray->direction * ( -ray->origin.z() / ray->direction.z() );
  };
  proposals = measure( 500'000, windows );
  ASSERT_TRUE( windows.windows[1] );
  EXPECT_EQ( windows.cut, std::vector<size_t> { 1 } );
  EXPECT_LE( windows.windows[1]->area(), 500'000 );
  ASSERT_TRUE( proposals[1].matched() ) << proposals[1].message;
  EXPECT_LT( ( proposals[1].pixelInImage - truth ).norm(), 0.05 );
  std::printf( "cut to 0.5 Mpx: right %d x %d px; peak resident memory of the process %ld MB\n", windows.windows[1]->width, windows.windows[1]->height,
               peakResidentMb() );
  // a window asked for beyond the limit is refused, not read
  EXPECT_THROW( cache.get( paths[1], cv::Rect( 0, 0, kSize, kSize ) ), std::invalid_argument );
  std::filesystem::remove_all( dir );
}
