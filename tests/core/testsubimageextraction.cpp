// Road-network extraction by sub-images (report §4: the 1024 x 1024
// mosaic, temporary dead ends at sub-image borders, runs until none are
// left): the image read window by window through a reader with a small
// tile cache finds the network the whole image finds, and GreyTiles on its
// own.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <tuple>
#include <stdexcept>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aerialpairs.h"
#include "extraction/coincidentextraction.h"
#include "extraction/greytiles.h"
#include "extraction/lineextractor.h"
#include "extraction/pairmapping.h"
#include "extraction/pairmatchwindows.h"
#include "extraction/roadnetworkextractor.h"
#include "io/rasterfile.h"
#include "matching/matchimage.h"

using namespace geostation;
using namespace geostation::testing;

namespace
{
  //! Reads windows of an image held in memory, as a raster file would be read, and counts the pixels read.
  GreyTiles readThroughTiles( const cv::Mat &grey, size_t cacheBytes, long *pixelsRead )
  {
    return GreyTiles(
      grey.size(),
      [grey, pixelsRead]( const cv::Rect &rect )
      {
        *pixelsRead += rect.area();
        return grey( rect ).clone();
      },
      cacheBytes );
  }
} // namespace

TEST( GreyTiles, WindowsEqualTheImageAndTheCacheStaysBounded )
{
  cv::Mat grey( 700, 1000, CV_8UC1 );
  cv::randu( grey, 0, 256 );
  long read = 0;
  const size_t limit = 6 * GreyTiles::kTilePx * GreyTiles::kTilePx; // 6 of the 12 tiles
  const GreyTiles tiles = readThroughTiles( grey, limit, &read );
  const GreyTiles whole( grey );
  EXPECT_FALSE( tiles.whole() );
  EXPECT_TRUE( whole.whole() );
  cv::RNG rng( 7 );
  for ( int i = 0; i < 200; ++i )
  {
    // windows anywhere, partly off the image, up to 600 px
    const cv::Rect rect( rng.uniform( -100, 1000 ), rng.uniform( -100, 700 ), rng.uniform( 1, 600 ), rng.uniform( 1, 600 ) );
    const GreyWindow a = tiles.window( rect ), b = whole.window( rect );
    const cv::Rect expected = rect & cv::Rect( 0, 0, 1000, 700 );
    ASSERT_EQ( a.rect(), expected );
    ASSERT_EQ( b.rect(), expected );
    if ( expected.empty() )
      continue;
    ASSERT_EQ( cv::norm( a.pixels, grey( expected ), cv::NORM_INF ), 0.0 );
    ASSERT_EQ( cv::norm( b.pixels, grey( expected ), cv::NORM_INF ), 0.0 );
    ASSERT_EQ( b.pixels.data, grey( expected ).data ) << "a window of an image held whole is a view";
    ASSERT_LE( tiles.cachedBytes(), limit + GreyTiles::kTilePx * GreyTiles::kTilePx );
  }
  EXPECT_LE( tiles.peakCachedBytes(), limit + GreyTiles::kTilePx * GreyTiles::kTilePx );
  EXPECT_GT( tiles.tilesRead(), 12 ) << "tiles evicted were read again";
  // coordinates: pixelInImage = pixelInWindow + origin
  const GreyWindow w = tiles.around( Eigen::Vector2d( 500.5, 300.5 ), 10 );
  EXPECT_EQ( w.rect(), cv::Rect( 490, 290, 22, 22 ) ); // the pixels 500 +- 10 and the next one, for interpolation
  EXPECT_TRUE( w.toWindow( Eigen::Vector2d( 500.5, 300.5 ) ).isApprox( Eigen::Vector2d( 10.5, 10.5 ) ) );
  EXPECT_TRUE( tiles.covering( Eigen::Vector2d( 1e30, 5 ), Eigen::Vector2d( 2e30, 6 ), 3 ).pixels.empty() );

  // a reader that fails: its error reaches the caller; one that returns the wrong pixels: a clear error
  const GreyTiles failing( cv::Size( 300, 300 ), []( const cv::Rect & ) -> cv::Mat { throw std::runtime_error( "disk error" ); } );
  EXPECT_THROW( failing.window( cv::Rect( 0, 0, 10, 10 ) ), std::runtime_error );
  const GreyTiles wrong( cv::Size( 300, 300 ), []( const cv::Rect & ) { return cv::Mat( 5, 5, CV_8UC3 ); } );
  EXPECT_THROW( wrong.window( cv::Rect( 0, 0, 10, 10 ) ), std::runtime_error );
  EXPECT_THROW( GreyTiles( cv::Mat( 10, 10, CV_8UC3 ) ), std::invalid_argument );
  EXPECT_THROW( GreyTiles( cv::Size( 0, 5 ), []( const cv::Rect &r ) { return cv::Mat( r.size(), CV_8UC1 ); } ), std::invalid_argument );
}

TEST( LineExtraction, ALineLeadingBackThroughProcessedSubImagesIsFollowedInFurtherRuns )
{
  // a dark road 10 px wide from (700, 700) up and to the left to the image's edge, on a noisy field: continued from a
  // dead end at its lower end, it leads into sub-images that come before in raster order, four times
  cv::Mat grey( 768, 768, CV_8UC1 );
  cv::RNG rng( 5 );
  rng.fill( grey, cv::RNG::NORMAL, 120, 4 );
  const Eigen::Vector2d from( 700, 700 ), along( -0.8, -0.6 );
  cv::line( grey, cv::Point( 700, 700 ), cv::Point( 700 - 0.8 * 1000, 700 - 0.6 * 1000 ), cv::Scalar( 70 ), 10, cv::LINE_AA );
  LineExtractionOptions options;
  options.object.polarity = -1;
  options.object.minContrast = 25.0;
  options.object.minWidthPx = 6.0;
  options.object.maxWidthPx = 20.0;
  options.subImageSizePx = 256;
  DeadEnd start;
  start.state.pixelInImage = from + 20.0 * along;
  start.state.direction = along;
  start.state.widthPx = 10.0;
  start.state.contrast = 50.0;
  start.kind = DeadEndKind::Verification;

  ResultMatrix wholeMatrix( 768, 768 ), matrix( 768, 768 );
  LineExtractionOptions wholeOptions = options;
  wholeOptions.subImageSizePx = 768;
  const LineExtractionSummary whole = extractLines( grey, wholeMatrix, { start }, false, wholeOptions );
  long read = 0;
  const LineExtractionSummary parts = extractLines( readThroughTiles( grey, 1 << 20, &read ), matrix, { start }, false, options );
  // the road leaves the image at x = 0 where y = 175; LEM stops a width short of the edge
  const double expected = ( start.state.pixelInImage.x() - 15.0 ) / 0.8;
  std::printf( "a line through five sub-images: whole %.0f px, by sub-images %.0f px (expected about %.0f) in %d runs, %d temporary dead ends\n", whole.linePx,
               parts.linePx, expected, parts.subImageRuns, parts.temporaryDeadEnds );
  EXPECT_EQ( parts.subImageRuns, 5 ) << "(2,2) -> (2,1) -> (1,1) -> (1,0) -> (0,0): each before the last in raster order";
  EXPECT_GE( parts.temporaryDeadEnds, 4 );
  ASSERT_EQ( parts.deadEnds.size(), 1u );
  EXPECT_EQ( parts.deadEnds[0].kind, DeadEndKind::ImageBorder );
  EXPECT_LT( parts.deadEnds[0].state.pixelInImage.x(), 30.0 );
  EXPECT_NEAR( parts.linePx, expected, 0.05 * expected );
  EXPECT_NEAR( parts.linePx, whole.linePx, 0.02 * whole.linePx );

  // with fewer runs than the line needs, it is left at a sub-image border and says so
  options.maxSubImageRuns = 3;
  ResultMatrix cut( 768, 768 );
  const LineExtractionSummary short3 = extractLines( readThroughTiles( grey, 1 << 20, &read ), cut, { start }, false, options );
  ASSERT_EQ( short3.deadEnds.size(), 1u );
  EXPECT_EQ( short3.deadEnds[0].kind, DeadEndKind::SubImageBorder );
  EXPECT_LT( short3.linePx, 0.8 * parts.linePx );
}

TEST( RoadExtraction, SubImagesOfOneImageFindItsRoads )
{
  const AerialPair &pair = aerialPair();
  const LineExtractionOptions wholeOptions = aerialOptions();
  ResultMatrix wholeMatrix( pair.left.cols, pair.left.rows );
  const LineExtractionSummary whole = extractLines( pair.left, wholeMatrix, {}, true, wholeOptions );

  // 16 sub-images of 256 px, read through 256 KiB of cached tiles (a quarter of the image)
  LineExtractionOptions options = aerialOptions();
  options.subImageSizePx = 256;
  long read = 0;
  const GreyTiles tiles = readThroughTiles( pair.left, 256 << 10, &read );
  ResultMatrix matrix( pair.left.cols, pair.left.rows );
  const LineExtractionSummary parts = extractLines( tiles, matrix, {}, true, options );

  const auto truth = truthCentreLinesInImage( pair, 0 );
  const BufferScore wholeScore = scoreInImage( asLines( compileMaxLengthPolygons( wholeMatrix, "S*+", false ).polygons ), truth, 2.0 );
  const BufferScore partsScore = scoreInImage( asLines( compileMaxLengthPolygons( matrix, "S*+", false ).polygons ), truth, 2.0 );
  std::printf( "one image: whole %.3f / %.3f, %.0f px of line; 16 sub-images %.3f / %.3f, %.0f px of line, %d runs, %d sub-images processed, "
               "%d temporary dead ends; %.2f Mpx read (the image: %.2f), peak cache %.0f KiB\n",
               wholeScore.completeness, wholeScore.correctness, whole.linePx, partsScore.completeness, partsScore.correctness, parts.linePx,
               parts.subImageRuns, parts.subImages, parts.temporaryDeadEnds, read / 1e6, pair.left.total() / 1e6, tiles.peakCachedBytes() / 1024.0 );
  EXPECT_GT( parts.temporaryDeadEnds, 0 ) << "the roads cross sub-image borders";
  for ( const DeadEnd &d : parts.deadEnds )
    EXPECT_NE( d.kind, DeadEndKind::SubImageBorder ) << "a line was left at a sub-image border at " << d.state.pixelInImage.transpose();
  EXPECT_GT( partsScore.completeness, wholeScore.completeness - 0.03 );
  EXPECT_GT( partsScore.correctness, 0.95 );
  EXPECT_NEAR( parts.linePx, whole.linePx, 0.08 * whole.linePx );
  EXPECT_LE( tiles.peakCachedBytes(), ( 256u << 10 ) + GreyTiles::kTilePx * GreyTiles::kTilePx );
}

TEST( RoadExtraction, SubImagesOfPairsGiveTheWholePairsNetworks )
{
  // the preset and five more seeds, each extracted from the images held whole (1024 x 1024: one sub-image) and by
  // 16 sub-images of 256 px read through 256 KiB of cached tiles: lines found from other starting points, continued
  // across borders, verified window by window
  struct Totals
  {
    double completeness = 0, correctness = 0, worstCorrectness = 1;
    size_t intersections = 0;
  } whole, parts;
  int temporary = 0, subImages = 0;
  size_t peakCache = 0;
  const std::vector<uint32_t> seeds { 3, 1, 2, 4, 5, 6 };
  for ( const uint32_t seed : seeds )
  {
    const AerialPair &pair = seed == 3 ? aerialPair() : seedPair( seed );
    const OrientedPairMapping mapping( pair.block.orientedImage( pair.block.images.at( 0 ) ), pair.block.orientedImage( pair.block.images.at( 1 ) ), meanRoadHeight( pair ) );
    CoincidentExtractionOptions options;
    options.extraction = aerialOptions();
    const CoincidentExtractionSummary w = extractCoincident( pair.left, pair.right, mapping, options );
    options.extraction.subImageSizePx = 256;
    long readA = 0, readB = 0;
    const GreyTiles a = readThroughTiles( pair.left, 256 << 10, &readA ), b = readThroughTiles( pair.right, 256 << 10, &readB );
    const CoincidentExtractionSummary p = extractCoincident( a, b, mapping, options );
    const auto truthA = truthCentreLinesInImage( pair, 0, true ), truthB = truthCentreLinesInImage( pair, 1, true );
    const double n = 2.0 * seeds.size();
    for ( const auto &[summary, totals] : { std::pair( &w, &whole ), std::pair( &p, &parts ) } )
    {
      const BufferScore sa = scoreInImage( asLines( summary->linesA ), truthA, 2.0 ), sb = scoreInImage( asLines( summary->linesB ), truthB, 2.0 );
      totals->completeness += ( sa.completeness + sb.completeness ) / n;
      totals->correctness += ( sa.correctness + sb.correctness ) / n;
      totals->worstCorrectness = std::min( { totals->worstCorrectness, sa.correctness, sb.correctness } );
      totals->intersections += summary->intersectionsA.size() + summary->intersectionsB.size();
      std::printf( "seed %u %s: A %.3f / %.3f, B %.3f / %.3f, %zu + %zu intersections\n", seed, summary == &w ? "whole" : "by sub-images", sa.completeness,
                   sa.correctness, sb.completeness, sb.correctness, summary->intersectionsA.size(), summary->intersectionsB.size() );
    }
    if ( const char *out = std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
      for ( int image = 0; image < 2; ++image )
      {
        cv::Mat canvas;
        cv::cvtColor( image == 0 ? pair.left : pair.right, canvas, cv::COLOR_GRAY2BGR );
        for ( const CompiledPolygon &line : image == 0 ? p.linesA : p.linesB )
          for ( size_t i = 0; i + 1 < line.pixels.size(); ++i )
            cv::line( canvas, cv::Point2d( line.pixels[i].x() - 0.5, line.pixels[i].y() - 0.5 ),
                      cv::Point2d( line.pixels[i + 1].x() - 0.5, line.pixels[i + 1].y() - 0.5 ), cv::Scalar( 0, 0, 255 ), 1 );
        for ( const Eigen::Vector2d &x : image == 0 ? p.intersectionsA : p.intersectionsB )
          cv::circle( canvas, cv::Point2d( x.x() - 0.5, x.y() - 0.5 ), 5, cv::Scalar( 0, 255, 255 ), 1 );
        cv::imwrite( std::string( out ) + "/subimages-seed" + std::to_string( seed ) + ( image == 0 ? "A" : "B" ) + ".png", canvas );
      }
    temporary += p.temporaryDeadEnds;
    subImages += p.subImages;
    peakCache = std::max( { peakCache, a.peakCachedBytes(), b.peakCachedBytes() } );
  }
  std::printf( "six pairs: whole %.3f / %.3f (worst correctness %.3f), %zu intersections; by sub-images %.3f / %.3f (worst %.3f), %zu intersections; "
               "%d sub-images processed, %d temporary dead ends, peak tile cache %.0f KiB\n",
               whole.completeness, whole.correctness, whole.worstCorrectness, whole.intersections, parts.completeness, parts.correctness, parts.worstCorrectness,
               parts.intersections, subImages, temporary, peakCache / 1024.0 );
  EXPECT_GT( temporary, 6 * 2 ) << "the roads cross sub-image borders";
  EXPECT_GT( parts.completeness, whole.completeness - 0.02 );
  EXPECT_GT( parts.correctness, whole.correctness - 0.02 );
  EXPECT_GT( parts.completeness, 0.90 );
  EXPECT_GT( parts.correctness, 0.95 );
  EXPECT_LE( peakCache, ( 256u << 10 ) + GreyTiles::kTilePx * GreyTiles::kTilePx );
}

TEST( RoadExtraction, APairReadInWindowsGivesTheSame3DNetwork )
{
  // the whole procedure - terrain height by matching, extraction, 3-D lines - on images held whole, and on the same
  // images read in windows: grey tiles through 1 MiB of cache, matching windows grown 128 px around what a match needs
  const AerialPair &pair = aerialPair();
  const OrientedImage a = pair.block.orientedImage( pair.block.images.at( 0 ) ), b = pair.block.orientedImage( pair.block.images.at( 1 ) );
  RoadNetworkOptions options;
  options.coincident.extraction = aerialOptions();
  const MatchImage wholeA( pair.left ), wholeB( pair.right );
  const RoadNetworkSummary whole = extractRoadNetwork( wholeA, wholeB, &a, &b, options );

  long readA = 0, readB = 0;
  const GreyTiles greyA = readThroughTiles( pair.left, 1 << 20, &readA ), greyB = readThroughTiles( pair.right, 1 << 20, &readB );
  long matchPixelsRead = 0;
  const MatchWindowSource source = [&]( int image, const cv::Rect &window )
  {
    const cv::Mat &pixels = image == 0 ? pair.left : pair.right;
    const cv::Rect held = matchingWindowToRead( window, pixels.size() );
    matchPixelsRead += held.area();
    return std::make_shared<const MatchImage>( pixels( held ).clone(), held.tl(), pixels.size() );
  };
  PairMatchWindows matching( source, pair.left.size(), pair.right.size(), 128, 0 ); // windows even of these small images
  const RoadNetworkSummary windowed = extractRoadNetwork( greyA, greyB, matching, &a, &b, options );

  // the 3-D vertices of the windowed run against the whole run's
  std::vector<Eigen::Vector3d> wholePoints;
  for ( const NetworkLine &line : whole.network.lines )
    for ( const NetworkVertex &v : line.vertices )
      wholePoints.push_back( v.point );
  int same = 0, vertices = 0;
  double worst = 0.0;
  for ( const NetworkLine &line : windowed.network.lines )
    for ( const NetworkVertex &v : line.vertices )
    {
      double nearest = std::numeric_limits<double>::infinity();
      for ( const Eigen::Vector3d &p : wholePoints )
        nearest = std::min( nearest, ( p - v.point ).norm() );
      ++vertices;
      same += nearest < 0.02;
      worst = std::max( worst, nearest );
    }
  const size_t wholeBytes = wholeA.bytes() + wholeB.bytes();
  std::printf( "windows: terrain %.2f m (whole %.2f m); %d 3-D vertices (whole %zu), %d within 2 cm of the whole run's, worst %.3f m; %d by area matching "
               "(whole %d); %ld matching windows, %.1f Mpx read, peak %.1f MB held (the whole images: %.1f MB)\n",
               windowed.meanHeightM, whole.meanHeightM, vertices, wholePoints.size(), same, worst, windowed.network.byArea, whole.network.byArea,
               matching.windowsRead(), matchPixelsRead / 1e6, matching.peakBytes() / 1e6, wholeBytes / 1e6 );
  EXPECT_NEAR( windowed.meanHeightM, whole.meanHeightM, 0.05 );
  EXPECT_EQ( windowed.extraction.linesA.size(), whole.extraction.linesA.size() );
  EXPECT_EQ( static_cast<size_t>( vertices ), wholePoints.size() );
  EXPECT_GE( same, 0.98 * vertices );
  EXPECT_GT( windowed.network.byArea, 0.9 * whole.network.byArea );
  EXPECT_GT( matching.windowsRead(), 4 );
  EXPECT_LT( matching.peakBytes(), wholeBytes / 2 );
}

TEST( RoadExtraction, ASixteenBitPairReadInWindowsIsScaledLikeTheWholeImages )
{
  // the preset pair as 16-bit GeoTIFFs (grey x 200 + 1000): read in windows, each tile and matching window is scaled by
  // the image's whole grey range, read once first - the same grey levels, so the same network, as decoding them whole
  const AerialPair &pair = aerialPair();
  const std::string left = ( pair.dir / "left16.tif" ).string(), right = ( pair.dir / "right16.tif" ).string();
  for ( const auto &[grey, path] : { std::pair( &pair.left, left ), std::pair( &pair.right, right ) } )
  {
    cv::Mat deep;
    grey->convertTo( deep, CV_16U, 200.0, 1000.0 );
    writeGeoTiffLike( path, deep, RasterImage() );
  }
  const OrientedImage a = pair.block.orientedImage( pair.block.images.at( 0 ) ), b = pair.block.orientedImage( pair.block.images.at( 1 ) );
  RoadNetworkOptions options;
  options.coincident.extraction = aerialOptions();
  const RoadNetworkSummary whole = extractRoadNetwork( MatchImage( readRaster( left ).pixels ), MatchImage( readRaster( right ).pixels ), &a, &b, options );

  const auto readerLeft = std::make_shared<const RasterReader>( left ), readerRight = std::make_shared<const RasterReader>( right );
  ASSERT_FALSE( readerLeft->eightBit() );
  const std::pair<double, double> range = greyRangeOf( *readerLeft );
  double lo = 0, hi = 0;
  cv::minMaxLoc( pair.left, &lo, &hi );
  EXPECT_EQ( range.first, lo * 200 + 1000 );
  EXPECT_EQ( range.second, hi * 200 + 1000 );
  // small tiles and windows, so that they are many
  PairMatchWindows matching( matchWindowsOf( readerLeft, readerRight ), readerLeft->size(), readerRight->size(), 128, 0 );
  const RoadNetworkSummary windowed = extractRoadNetwork( greyTilesOf( readerLeft, std::nullopt, 1 << 20 ), greyTilesOf( readerRight, std::nullopt, 1 << 20 ),
                                                          matching, &a, &b, options );
  std::printf( "16 bits: whole %zu + %zu lines, %d 3-D vertices, terrain %.2f m; in windows %zu + %zu lines, %d 3-D vertices, terrain %.2f m (%ld matching windows)\n",
               whole.extraction.linesA.size(), whole.extraction.linesB.size(), whole.network.vertices - whole.network.unmatched, whole.meanHeightM,
               windowed.extraction.linesA.size(), windowed.extraction.linesB.size(), windowed.network.vertices - windowed.network.unmatched, windowed.meanHeightM,
               windowed.reading.matchingWindows );
  EXPECT_TRUE( windowed.reading.inWindows );
  EXPECT_GT( windowed.reading.matchingWindows, 4 );
  EXPECT_NEAR( windowed.meanHeightM, whole.meanHeightM, 0.05 );
  ASSERT_EQ( windowed.extraction.linesA.size(), whole.extraction.linesA.size() );
  for ( size_t i = 0; i < whole.extraction.linesA.size(); ++i )
    EXPECT_EQ( windowed.extraction.linesA[i].pixels, whole.extraction.linesA[i].pixels ) << "line " << i;
  EXPECT_EQ( windowed.network.vertices - windowed.network.unmatched, whole.network.vertices - whole.network.unmatched );
}
