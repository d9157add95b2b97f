// Matching on real photographs seen by oriented cameras from strongly
// different viewpoints (thesis ch. 5, "large geometric distortion"): a real
// aerial photograph (opencv-doc's aero1.jpg) and a real wall photograph
// (graf1.png) are laid on a ground surface - a plane, or a hilly DEM - and
// rendered exactly through each camera (ray / surface, the photograph
// sampled where the ray lands), so the truth of every conjugate point is the
// reference pixel's ground point projected into the other image. Not the
// simulator's renderer: another texture, another surface model, another
// sampling. The Multiview's proposals (epipolar band, LSM, checks) are run
// with and without the window shape predicted from the surface.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dem/demintersection.h"
#include "geometry/rotation.h"
#include "geometry/windowshape.h"
#include "matchscore.h"
#include "syntheticterrain.h"
#include "texturedground.h"
#include "workstation/pointmeasurer.h"

using namespace geostation;
using namespace texturedground;

namespace
{
  /**
   * Corners of the reference image (Shi-Tomasi, as an operator picks
   * well-defined points) on the texture and seen in the search image,
   * proposed in the search image as the Multiview does; errors against the
   * truth through the surface.
   */
  MatchScore proposeWithTruth( const OrientedImage &reference, const cv::Mat &referencePixels, const OrientedImage &search, const cv::Mat &searchPixels,
                               const GroundTexture &t, const GroundOfPixel &surface, bool predictShape )
  {
    const MatchImage a( referencePixels ), b( searchPixels );
    const std::vector<MeasurementView> views { { "reference", &reference, &a }, { "search", &search, &b } };
    ProposalOptions options;
    options.epipolar.maxDistanceM = 150.0;
    if ( predictShape )
      options.groundOfPixel = surface;
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack( a.grey(), corners, 300, 0.01, 12 );
    MatchScore score;
    for ( const cv::Point2f &corner : corners )
    {
      const Eigen::Vector2d p( corner.x + 0.5, corner.y + 0.5 );
      const std::optional<Eigen::Vector3d> ground = surface( reference, p );
      if ( !ground || !t.covers( *ground, 15 ) || p.x() < 25 || p.y() < 25 || p.x() > a.width() - 25 || p.y() > a.height() - 25 )
        continue;
      const GroundProjection truth = search.projectGroundToPixel( *ground );
      if ( !truth.ok() || truth.pixelInImage.x() < 25 || truth.pixelInImage.y() < 25 || truth.pixelInImage.x() > b.width() - 25 ||
           truth.pixelInImage.y() > b.height() - 25 )
        continue;
      const ConjugateProposal proposal = proposeConjugates( views, 0, p, options )[1];
      if ( !proposal.matched() && std::getenv( "GEOSTATION_SHAPE_DEBUG" ) )
        std::printf( "  %s: %s\n", matchStatusName( proposal.status ).c_str(), proposal.message.c_str() );
      score.add( matchStatusName( proposal.status ), proposal.matched(), ( proposal.pixelInImage - truth.pixelInImage ).norm() );
    }
    return score;
  }


  //! Issue bar for real photographs (>= 65 % within 1 px, median <= 0.4 px, <= 5 % of returned matches wrong), and clearly better than square windows.
  void expectShapedMeetsTheBar( const MatchScore &square, const MatchScore &shaped )
  {
    ASSERT_GE( shaped.attempted, 60 );
    EXPECT_GE( shaped.within1Fraction(), 0.65 );
    EXPECT_LE( shaped.median, 0.4 );
    EXPECT_LE( shaped.wrongFraction(), 0.05 );
    EXPECT_GT( shaped.within1Fraction(), square.within1Fraction() + 0.1 );
  }

  //! Proposals on one pair with square windows and with the predicted shape, printed and held to the bar.
  void compareWindows( const std::string &name, const OrientedImage &reference, const cv::Mat &referencePixels, const OrientedImage &search,
                       const cv::Mat &searchPixels, const GroundTexture &t, const GroundOfPixel &surface )
  {
    const MatchScore square = proposeWithTruth( reference, referencePixels, search, searchPixels, t, surface, false );
    const MatchScore shaped = proposeWithTruth( reference, referencePixels, search, searchPixels, t, surface, true );
    square.print( name + ", square windows" );
    shaped.print( name + ", predicted shape" );
    expectShapedMeetsTheBar( square, shaped );
  }
}

TEST( WindowShape, PredictedShapeIsThePlaneInducedMapping )
{
  // two cameras over the plane Z = 0: the predicted Jacobian equals the derivative of the plane's homography
  const Camera camera = frameCamera( 800, 600, 700.0 );
  const OrientedImage a = lookingAt( camera, Eigen::Vector3d( 0, -10, 3 ), 0.0, 20.0 );
  const OrientedImage b = lookingAt( camera, Eigen::Vector3d( 4, -2, 3 ), -130.0, 30.0 );
  const GroundOfPixel plane = groundPlane( 0.0 );
  const Eigen::Vector2d p( 430.0, 470.0 );
  const std::optional<PredictedWindow> w = predictWindowShape( a, p, b, plane, 1.0 );
  ASSERT_TRUE( w );
  EXPECT_NEAR( w->groundPoint.z(), 0.0, 1e-9 );
  EXPECT_LT( ( b.projectGroundToPixel( w->groundPoint ).pixelInImage - w->pixelInSearch ).norm(), 1e-9 );
  // the plane homography's derivative by small steps
  for ( int k = 0; k < 2; ++k )
  {
    const Eigen::Vector2d step = 1e-4 * Eigen::Vector2d::Unit( k );
    const Eigen::Vector2d ahead = b.projectGroundToPixel( *plane( a, p + step ) ).pixelInImage, behind = b.projectGroundToPixel( *plane( a, p - step ) ).pixelInImage;
    EXPECT_LT( ( ( ahead - behind ) / 2e-4 - w->searchFromReference.col( k ) ).norm(), 1e-3 * w->searchFromReference.norm() );
  }
  // far from identity: a strongly distorted pair
  EXPECT_GT( ( w->searchFromReference - Eigen::Matrix2d::Identity() ).norm(), 0.5 );
  // the same camera: identity
  const std::optional<PredictedWindow> same = predictWindowShape( a, p, a, plane );
  ASSERT_TRUE( same );
  EXPECT_LT( ( same->searchFromReference - Eigen::Matrix2d::Identity() ).norm(), 1e-6 );
  // a pixel above the horizon misses the plane; a non-positive step is a programming error
  EXPECT_FALSE( predictWindowShape( a, Eigen::Vector2d( 400, 10 ), b, plane ) );
  EXPECT_FALSE( predictWindowShape( a, p, b, GroundOfPixel() ) );
  EXPECT_THROW( predictWindowShape( a, p, b, plane, 0.0 ), std::invalid_argument );
}

TEST( WindowShape, RoadSurfaceFromTwoStationsOfARun )
{
  // a real aerial photograph as the road surface, 12 mm per pixel, seen by a forward camera 2.5 m above
  // it, 30 degrees down, from two stations 4 m apart: the near station sees the surface at about twice
  // the scale and much less foreshortened than the far one
  const GroundTexture t = texture( "aero1.jpg", 0.012, Eigen::Vector2d( 0.0, 6.0 ) );
  ASSERT_FALSE( t.grey.empty() ) << "opencv-doc's example data (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const Camera camera = frameCamera( 1024, 768, 900.0 );
  const GroundOfPixel plane = groundPlane( 0.0 );
  const OrientedImage nearStation = lookingAt( camera, Eigen::Vector3d( 0.0, 1.0, 2.5 ), 0.0, 30.0 );
  const OrientedImage farStation = lookingAt( camera, Eigen::Vector3d( 0.0, -3.0, 2.5 ), 0.0, 30.0 );
  const cv::Mat nearPixels = render( nearStation, t, plane, 1 ), farPixels = render( farStation, t, plane, 2 );

  for ( const bool nearIsReference : { true, false } )
  {
    const OrientedImage &reference = nearIsReference ? nearStation : farStation, &search = nearIsReference ? farStation : nearStation;
    const cv::Mat &referencePixels = nearIsReference ? nearPixels : farPixels, &searchPixels = nearIsReference ? farPixels : nearPixels;
    const std::string name = nearIsReference ? "road, near station -> far" : "road, far station -> near";
    compareWindows( name, reference, referencePixels, search, searchPixels, t, plane );
  }
}

TEST( WindowShape, ObliquePairSixtyDegreesApart )
{
  // a real wall photograph laid flat, seen from 45 degrees above the horizon by two cameras 60 degrees apart in azimuth
  const GroundTexture t = texture( "graf1.png", 0.01, Eigen::Vector2d( 0.0, 0.0 ) );
  ASSERT_FALSE( t.grey.empty() ) << "opencv-doc's example data (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const Camera camera = frameCamera( 1024, 768, 1100.0 );
  const GroundOfPixel plane = groundPlane( 0.0 );
  const auto fromAzimuth = [&]( double azimuthDeg )
  {
    const double a = degToRad( azimuthDeg ), d = 8.0;
    // standing d metres back (horizontally) from the centre, opposite to the viewing azimuth
    return lookingAt( camera, Eigen::Vector3d( -d * std::sin( a ), -d * std::cos( a ), d ), azimuthDeg, 45.0 );
  };
  const OrientedImage left = fromAzimuth( -30.0 ), right = fromAzimuth( 30.0 );
  const cv::Mat leftPixels = render( left, t, plane, 3 ), rightPixels = render( right, t, plane, 4 );
  compareWindows( "graffiti, 60 deg apart", left, leftPixels, right, rightPixels, t, plane );
}

TEST( WindowShape, HillyTerrainThroughTheDem )
{
  // the aerial photograph draped over hills 12 m high (the DEM test terrain), seen obliquely from two
  // hill-side positions 90 degrees apart; the shape comes from the DEM, ray by ray
  const std::string path = syntheticterrain::tempPath( "shaped-dem" );
  syntheticterrain::writeTerrain( path, 200 );
  const Dem dem( path );
  const CrsTransform identity( "EPSG:32633", "EPSG:32633" );
  const GroundOfPixel surface = demGroundOfPixel( dem, identity );
  const Eigen::Vector2d centre( syntheticterrain::kX0 + 200.0, syntheticterrain::kY0 - 200.0 );
  const GroundTexture t = texture( "aero1.jpg", 0.1, centre );
  ASSERT_FALSE( t.grey.empty() ) << "opencv-doc's example data (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const Camera camera = frameCamera( 1024, 768, 1000.0 );
  const double groundZ = syntheticterrain::height( centre.x(), centre.y() );
  const OrientedImage south = lookingAt( camera, Eigen::Vector3d( centre.x(), centre.y() - 60.0, groundZ + 45.0 ), 0.0, 37.0 );
  const OrientedImage west = lookingAt( camera, Eigen::Vector3d( centre.x() - 60.0, centre.y(), groundZ + 45.0 ), 90.0, 37.0 );
  const cv::Mat southPixels = render( south, t, surface, 5 ), westPixels = render( west, t, surface, 6 );
  compareWindows( "hills (DEM), 90 deg apart", south, southPixels, west, westPixels, t, surface );
  std::remove( path.c_str() );
}
