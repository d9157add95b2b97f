// Road extraction on a real aerial photograph: opencv-doc's aero3.jpg (an
// oblique view over a town, roads 4 to 28 px wide among buildings, trees and
// fields), and its partner made by warping it with a known homography and
// adding noise. The pair is registered by control points, as an unoriented
// pair of extract_roads is. Ground truth:
// - the known homography: the lines of the two images must coincide through it;
// - the centre lines of three main roads (the highway, the road beside it,
//   the cross road), digitised by hand on the photograph, each with a
//   half-width that holds the road (aero3image.h);
// - two areas certainly without roads (the sea, the forest), where no line
//   may be found.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aero3image.h"
#include "debugdrawing.h"
#include "extraction/polygoncompilation.h"
#include "imagelinescoring.h"
#include "extraction/roadnetworkextractor.h"
#include "matching/matchimage.h"

using namespace geostation;

namespace
{
  using Polyline = PixelPolyline;

  std::vector<TruthRoad> mainRoads() { return aero3image::aero3MainRoads(); }
  std::vector<std::vector<cv::Point2f>> roadlessAreas() { return aero3image::aero3RoadlessAreas(); }

  //! The partner's homography on pixel indices (OpenCV): scale 0.92, 8 degrees, a perspective change.
  cv::Matx33d partnerFromPhoto()
  {
    const double angle = 8.0 * CV_PI / 180.0, scale = 0.92;
    return cv::Matx33d( scale * std::cos( angle ), -scale * std::sin( angle ), 60.0, scale * std::sin( angle ), scale * std::cos( angle ), 10.0, 1.5e-4, -1.0e-4, 1.0 );
  }

  //! A homography on pixel indices applied to a pixelInImage point (centres at i + 0.5).
  Eigen::Vector2d apply( const cv::Matx33d &h, const Eigen::Vector2d &p )
  {
    const cv::Vec3d q = h * cv::Vec3d( p.x() - 0.5, p.y() - 0.5, 1.0 );
    return Eigen::Vector2d( q[0] / q[2] + 0.5, q[1] / q[2] + 0.5 );
  }

  //! Completeness of `roads`: their length within half-width + tolerance of the result.
  double completenessOf( const std::vector<TruthRoad> &roads, const std::vector<Polyline> &result, double tolerancePx )
  {
    const auto [found, total] = lengthFound( roads, result, tolerancePx );
    return found / total;
  }

  double completeness( const std::vector<Polyline> &result, double tolerancePx ) { return completenessOf( mainRoads(), result, tolerancePx ); }

  struct Coincidence
  {
    double fraction = 0.0; //!< of the length of `lines` within the buffer of `reference`
    double medianPx = 0.0; //!< distance of those within it
  };

  Coincidence coincidence( const std::vector<Polyline> &lines, const std::vector<Polyline> &reference, double bufferPx )
  {
    double total = 0.0, within = 0.0;
    std::vector<double> distances;
    alongLines( lines, [&]( const Eigen::Vector2d &p, double length ) {
      total += length;
      const double d = distanceToLines( p, reference );
      if ( d <= bufferPx )
      {
        within += length;
        distances.push_back( d );
      }
    } );
    Coincidence c;
    c.fraction = total > 0 ? within / total : 0.0;
    if ( !distances.empty() )
    {
      std::nth_element( distances.begin(), distances.begin() + distances.size() / 2, distances.end() );
      c.medianPx = distances[distances.size() / 2];
    }
    return c;
  }

  std::vector<Polyline> linesOf( const std::vector<CompiledPolygon> &polygons, const cv::Matx33d *h = nullptr )
  {
    std::vector<Polyline> out;
    for ( const CompiledPolygon &p : polygons )
    {
      out.emplace_back();
      for ( const Eigen::Vector2d &v : p.pixels )
        out.back().push_back( h ? apply( *h, v ) : v );
    }
    return out;
  }

  double lengthInRoadlessAreas( const std::vector<Polyline> &lines ) { return lengthInAreas( lines, roadlessAreas() ); }

  struct RealPair
  {
    cv::Mat photo, partner;
    std::vector<ControlPair> control;
  };

  RealPair realPair( const std::string &file = "aero3.jpg" )
  {
    RealPair pair;
    pair.photo = cv::imread( aero3image::sampleImagePath( file ), cv::IMREAD_GRAYSCALE );
    if ( pair.photo.empty() )
      return pair;
    cv::Mat warped;
    cv::warpPerspective( pair.photo, warped, cv::Mat( partnerFromPhoto() ), pair.photo.size(), cv::INTER_CUBIC, cv::BORDER_CONSTANT, cv::Scalar( 0 ) );
    cv::RNG rng( 3 );
    cv::Mat noise( warped.size(), CV_32F );
    rng.fill( noise, cv::RNG::NORMAL, 0.0, 3.0 );
    cv::Mat noisy;
    warped.convertTo( noisy, CV_32F );
    noisy += noise;
    noisy.convertTo( pair.partner, CV_8U );
    // nine control points on a 3 x 3 grid, measured to about 0.3 px in each image
    for ( int r = 0; r < 3; ++r )
      for ( int c = 0; c < 3; ++c )
      {
        const Eigen::Vector2d inPhoto( 120.0 + 200.0 * c, 110.0 + 140.0 * r );
        const Eigen::Vector2d error( rng.gaussian( 0.3 ), rng.gaussian( 0.3 ) );
        pair.control.push_back( { "c" + std::to_string( 3 * r + c ), inPhoto, apply( partnerFromPhoto(), inPhoto ) + error } );
      }
    return pair;
  }

  RoadNetworkOptions realPhotoOptions()
  {
    RoadNetworkOptions options;
    LineExtractionOptions &extraction = options.coincident.extraction;
    extraction.object.polarity = 1; // asphalt lighter than the trees and roofs beside it
    extraction.object.minContrast = 12.0;
    extraction.object.maxVariation = 14.0;
    extraction.object.minWidthPx = 3.0;
    extraction.object.maxWidthPx = 16.0;
    extraction.start.sampleSpacingPx = 16; // a small image: the default 48 px leaves short roads without a starting point
    options.control = realPair().control;
    options.controlMapping = ControlMapping::Projective;
    return options;
  }

  struct Evaluation
  {
    double completenessPhoto = 0.0, completenessPartner = 0.0;
    Coincidence partnerInPhoto, photoInPartner;
    double roadlessPx = 0.0, lengthPx = 0.0;
  };

  Evaluation evaluate( const RoadNetworkSummary &s )
  {
    const cv::Matx33d photoFromPartner = partnerFromPhoto().inv();
    const std::vector<Polyline> photoLines = linesOf( s.extraction.linesA ), partnerLines = linesOf( s.extraction.linesB, &photoFromPartner );
    Evaluation e;
    e.completenessPhoto = completeness( photoLines, 3.0 );
    e.completenessPartner = completeness( partnerLines, 3.0 );
    e.partnerInPhoto = coincidence( partnerLines, photoLines, 3.0 );
    e.photoInPartner = coincidence( photoLines, partnerLines, 3.0 );
    e.roadlessPx = lengthInRoadlessAreas( photoLines ) + lengthInRoadlessAreas( partnerLines );
    e.lengthPx = totalLength( photoLines );
    return e;
  }

  //! With GEOSTATION_EXTRACTION_DEBUG set to a folder: the photograph with its lines (red), the partner's mapped back (green) and the roads of the truth (blue).
  void drawDebug( const std::string &name, const cv::Mat &photo, const RoadNetworkSummary &s, const std::vector<TruthRoad> &truth = mainRoads() )
  {
    const cv::Matx33d photoFromPartner = partnerFromPhoto().inv();
    std::vector<Polyline> truthLines;
    for ( const TruthRoad &road : truth )
      truthLines.push_back( road.centre );
    drawLinesForDebugging( name, photo, { { truthLines, cv::Scalar( 255, 0, 0 ) }, { linesOf( s.extraction.linesB, &photoFromPartner ), cv::Scalar( 0, 255, 0 ) },
                                          { linesOf( s.extraction.linesA ), cv::Scalar( 0, 0, 255 ) } } );
  }
} // namespace

TEST( RealAerialPhotograph, RoadsFoundAndVerifiedInAPartnerUnderAKnownHomography )
{
  const RealPair pair = realPair();
  ASSERT_FALSE( pair.photo.empty() ) << "aero3.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const MatchImage photo( pair.photo ), partner( pair.partner );
  const RoadNetworkSummary narrow = extractRoadNetwork( photo, partner, nullptr, nullptr, realPhotoOptions() );
  ASSERT_TRUE( narrow.registration );
  // nine points measured to 0.3 px: the verification searches about 3 px either side, not the 12 px of an unknown mapping
  std::printf( "registration: rms %.2f px, max %.2f px, expected %.2f px; verification searches %.1f px\n", narrow.registration->rmsPx,
               narrow.registration->maxPx, narrow.registration->expectedPx, narrow.verificationSearchPx );
  EXPECT_GE( narrow.verificationSearchPx, 3.0 );
  EXPECT_LE( narrow.verificationSearchPx, 4.5 );

  RoadNetworkOptions wideOptions = realPhotoOptions();
  // the four corner points alone cannot tell the misregistration: the full 12 px
  wideOptions.control = { wideOptions.control[0], wideOptions.control[2], wideOptions.control[6], wideOptions.control[8] };
  const RoadNetworkSummary wide = extractRoadNetwork( photo, partner, nullptr, nullptr, wideOptions );
  EXPECT_DOUBLE_EQ( wide.verificationSearchPx, wideOptions.coincident.verification.misregistrationPx );

  const Evaluation n = evaluate( narrow ), w = evaluate( wide );
  for ( const auto &[name, e] : { std::pair<const char *, const Evaluation &>( "search from the control points", n ), std::pair<const char *, const Evaluation &>( "search 12 px", w ) } )
    std::printf( "%s: %.0f px of lines; main roads found %.3f (photo) %.3f (partner); partner's lines on the photo's %.3f (median %.2f px), "
                 "photo's on the partner's %.3f (median %.2f px); %.0f px in roadless areas\n",
                 name, e.lengthPx, e.completenessPhoto, e.completenessPartner, e.partnerInPhoto.fraction, e.partnerInPhoto.medianPx,
                 e.photoInPartner.fraction, e.photoInPartner.medianPx, e.roadlessPx );

  drawDebug( "real_aerial", pair.photo, narrow );

  // the main roads are found in both images
  EXPECT_GT( n.completenessPhoto, 0.75 );
  EXPECT_GT( n.completenessPartner, 0.75 );
  // the two images' networks are the same lines: each within 3 px of the other through the known homography
  EXPECT_GT( n.partnerInPhoto.fraction, 0.82 );
  EXPECT_GT( n.photoInPartner.fraction, 0.85 );
  EXPECT_LT( n.partnerInPhoto.medianPx, 0.8 );
  EXPECT_LT( n.photoInPartner.medianPx, 0.8 );
  // the narrow search keeps verification from taking a parallel line beside the mapped one
  EXPECT_GT( n.partnerInPhoto.fraction + n.photoInPartner.fraction, w.partnerInPhoto.fraction + w.photoInPartner.fraction + 0.05 );
  // nothing where there is certainly no road
  EXPECT_EQ( n.roadlessPx, 0.0 );
  EXPECT_GT( n.lengthPx, 2000.0 );
}

TEST( RealAerialPhotograph, CloserSampleLinesFindMoreOfASmallImagesRoads )
{
  // extract_roads' START_SPACING_PX: the default 48 px suits large images; this one is 640 x 480
  const RealPair pair = realPair();
  ASSERT_FALSE( pair.photo.empty() ) << "aero3.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  std::vector<double> found;
  for ( int spacing : { 48, 16 } )
  {
    LineExtractionOptions options = realPhotoOptions().coincident.extraction;
    options.start.sampleSpacingPx = spacing;
    ResultMatrix matrix( pair.photo.cols, pair.photo.rows );
    const LineExtractionSummary s = extractLines( pair.photo, matrix, {}, true, options );
    const std::vector<Polyline> lines = linesOf( compileMaxLengthPolygons( matrix, "S*+", false ).polygons );
    found.push_back( completeness( lines, 3.0 ) );
    std::printf( "sample lines every %d px: %d starting points, %d lines, main roads found %.3f, %.0f px in roadless areas\n", spacing, s.startingPoints,
                 s.linesStarted, found.back(), lengthInRoadlessAreas( lines ) );
    EXPECT_EQ( lengthInRoadlessAreas( lines ), 0.0 );
  }
  EXPECT_GT( found[1], found[0] + 0.1 );
  EXPECT_GT( found[1], 0.8 );
}

// The same pair with extract_roads' defaults, as a user would run it: either polarity, 4 to 24 px (a pair
// registered by control points has no ground pixel), the contrast from the texture, sample lines 48 px apart.
TEST( RealAerialPhotograph, DefaultsOnTheMainRoads )
{
  const RealPair pair = realPair();
  ASSERT_FALSE( pair.photo.empty() ) << "aero3.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  RoadNetworkOptions options = defaultRoadNetworkOptions();
  options.control = pair.control;
  options.controlMapping = ControlMapping::Projective;
  const RoadNetworkSummary s = extractRoadNetwork( MatchImage( pair.photo ), MatchImage( pair.partner ), nullptr, nullptr, options );
  const Evaluation e = evaluate( s );
  drawDebug( "aero3_defaults", pair.photo, s );
  std::printf( "aero3 with the defaults: main roads' completeness %.2f (photo), %.2f (partner); %.0f px of line, %.0f px in the sea and forest; contrast %.0f\n",
               e.completenessPhoto, e.completenessPartner, e.lengthPx, e.roadlessPx, s.minContrast );
  for ( const TruthRoad &road : mainRoads() )
    std::printf( "  %s: %.2f found\n", road.name.c_str(), completenessOf( { road }, linesOf( s.extraction.linesA ), 3.0 ) );
  EXPECT_GE( e.completenessPhoto, 0.70 );
  EXPECT_LT( e.roadlessPx, 0.05 * e.lengthPx );
}

// opencv-doc's aero1.jpg: an oblique view of a town by a lake, the elevated highway crossing it 5-8 px wide
// (digitised by hand on the photograph at 4x, to about 2 px), a lake and a wood without roads; the partner
// made and registered as aero3's. With the defaults.
TEST( RealAerialPhotograph, Aero1HighwayWithTheDefaults )
{
  const RealPair pair = realPair( "aero1.jpg" );
  ASSERT_FALSE( pair.photo.empty() ) << "aero1.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const std::vector<TruthRoad> highway = { { "highway", 4.0, { { 447.5, 113.75 }, { 410, 127.5 }, { 372.5, 141.25 }, { 342.5, 153.75 }, { 322.5, 165 }, { 305, 176.25 },
                                                               { 290, 188.75 }, { 280, 197.5 } } } };
  const std::vector<std::vector<cv::Point2f>> roadless = { { { 330, 430 }, { 450, 425 }, { 465, 470 }, { 320, 475 } }, { { 0, 405 }, { 150, 405 }, { 150, 480 }, { 0, 480 } } };
  RoadNetworkOptions options = defaultRoadNetworkOptions();
  options.control = pair.control;
  options.controlMapping = ControlMapping::Projective;
  const RoadNetworkSummary s = extractRoadNetwork( MatchImage( pair.photo ), MatchImage( pair.partner ), nullptr, nullptr, options );
  const std::vector<Polyline> lines = linesOf( s.extraction.linesA );
  drawDebug( "aero1_defaults", pair.photo, s, highway );
  const double found = completenessOf( highway, lines, 3.0 ), wrong = lengthInAreas( lines, roadless );
  std::printf( "aero1 with the defaults: the highway %.2f found; %.0f px of line, %.0f px in the lake and the wood; contrast %.0f\n", found, totalLength( lines ), wrong,
               s.minContrast );
  EXPECT_GE( found, 0.70 );
  EXPECT_EQ( wrong, 0.0 );
}
