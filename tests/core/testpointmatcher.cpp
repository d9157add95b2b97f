// PointMatcher, what geostation:match_points runs for every point: a real
// photograph's texture (opencv-doc's aero1.jpg) on flat ground seen by two
// nadir frames 100 m apart, found along the epipolar band of the oriented
// pair and, with the orientations removed, around an approximate position;
// and each expected failure with its reason.
#include <filesystem>
#include <unistd.h>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "workstation/pointmatcher.h"

using namespace geostation;

namespace
{
  struct FlatPair
  {
    std::filesystem::path dir;
    Block block;
    Eigen::Vector2d pixelInLeft, truthInRight;
  };

  //! Two 800 x 800 nadir frames 500 m above flat ground, 100 m apart (the ground moves 200 px), the photograph on the ground.
  FlatPair flatPair( const cv::Mat &photo )
  {
    FlatPair p;
    p.dir = std::filesystem::temp_directory_path() / ( "geostation-pointmatcher-" + std::to_string( ::getpid() ) );
    std::filesystem::create_directories( p.dir );
    Camera camera;
    camera.id = "nadir";
    camera.width = camera.height = 800;
    camera.f = 1000.0;
    camera.cx = camera.cy = 400.0;
    p.block.crs = "EPSG:32617";
    p.block.cameras.push_back( camera );
    p.block.sourceFile = p.dir / "block.geostation.json";
    const cv::Mat ground = photo( cv::Rect( 0, 0, 600, 400 ) );
    for ( int i = 0; i < 2; ++i )
    {
      cv::Mat frame( 800, 800, CV_8UC1, cv::Scalar( 0 ) );
      ground.copyTo( frame( cv::Rect( i == 0 ? 200 : 0, 200, 600, 400 ) ) ); // the right frame sees the ground 200 px further left
      const std::string name = i == 0 ? "left.png" : "right.png";
      cv::imwrite( ( p.dir / name ).string(), frame );
      BlockImage image;
      image.id = i == 0 ? "L" : "R";
      image.cameraId = camera.id;
      image.path = name;
      ExteriorOrientation eo;
      eo.projectionCentre = Eigen::Vector3d( 500000.0 + 100.0 * i, 4400000.0, 500.0 );
      image.exterior = eo;
      p.block.images.push_back( image );
    }
    p.pixelInLeft = Eigen::Vector2d( 420.3, 371.8 );
    p.truthInRight = p.pixelInLeft - Eigen::Vector2d( 200.0, 0.0 );
    return p;
  }
} // namespace

TEST( PointMatcher, AlongTheEpipolarBandAndAroundAnApproximatePosition )
{
  const cv::Mat photo = cv::imread( "/usr/share/doc/opencv-doc/examples/data/aero1.jpg", cv::IMREAD_GRAYSCALE );
  ASSERT_FALSE( photo.empty() ) << "aero1.jpg (Debian package opencv-doc)";
  FlatPair pair = flatPair( photo );
  PointMatchOptions options;
  options.area.windowWidth = options.area.windowHeight = 21;
  options.epipolar.minDistanceM = 100.0;
  options.epipolar.maxDistanceM = 2000.0;
  MatchImageCache cache;
  {
    const PointMatcher matcher( pair.block, options, cache );
    const AreaMatch m = matcher.match( pair.block.images[0], pair.pixelInLeft, pair.block.images[1], std::nullopt );
    ASSERT_TRUE( m.matched() ) << m.message;
    EXPECT_EQ( m.status, MatchStatus::Lsm );
    EXPECT_LT( ( m.pixelInImage - pair.truthInRight ).norm(), 0.05 );
    // the point outside its image; the curve outside the target (a point whose ground the right frame does not see)
    EXPECT_EQ( matcher.match( pair.block.images[0], Eigen::Vector2d( -5, 10 ), pair.block.images[1], std::nullopt ).message, "the point lies outside the reference image" );
    const AreaMatch off = matcher.match( pair.block.images[1], Eigen::Vector2d( 790, 400 ), pair.block.images[0], std::nullopt );
    EXPECT_FALSE( off.matched() );
  }
  // unoriented: around an approximate position (6 px off), or not at all without one
  for ( BlockImage &image : pair.block.images )
    image.exterior.reset();
  {
    const PointMatcher matcher( pair.block, options, cache );
    const AreaMatch m = matcher.match( pair.block.images[0], pair.pixelInLeft, pair.block.images[1], pair.truthInRight + Eigen::Vector2d( 4.0, -4.5 ) );
    ASSERT_TRUE( m.matched() ) << m.message;
    EXPECT_LT( ( m.pixelInImage - pair.truthInRight ).norm(), 0.05 );
    EXPECT_EQ( matcher.match( pair.block.images[0], pair.pixelInLeft, pair.block.images[1], std::nullopt ).message,
               "the images are not both oriented and the point has no approximate position in the target" );
    const AreaMatch outside = matcher.match( pair.block.images[0], pair.pixelInLeft, pair.block.images[1], Eigen::Vector2d( 900, 100 ) );
    EXPECT_EQ( outside.status, MatchStatus::Outside );
    EXPECT_EQ( outside.message, "every search window leaves the search image or is flat" );
  }
  // an image that cannot be read is named in the reason
  std::filesystem::remove( pair.dir / "right.png" );
  cache.clear();
  const PointMatcher matcher( pair.block, options, cache );
  const AreaMatch m = matcher.match( pair.block.images[0], pair.pixelInLeft, pair.block.images[1], pair.truthInRight );
  EXPECT_FALSE( m.matched() );
  EXPECT_EQ( m.message.rfind( "the image R cannot be read: ", 0 ), 0u ) << m.message;
  // bad options: one sentence
  options.epipolar.maxDistanceM = 50.0;
  EXPECT_THROW( PointMatcher( pair.block, options, cache ), std::invalid_argument );
  std::filesystem::remove_all( pair.dir );
}
