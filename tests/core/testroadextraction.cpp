// Road-network extraction (core/extraction) against the simulator's truth:
// an aerial stereo pair at 0.5 m ground pixels with three roads (curves,
// two junctions, 6 and 7 m wide), trees and their shadows, fields, image
// noise; and the pieces on hand-made images.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "extraction/crossprofile.h"
#include "extraction/lineextractor.h"
#include "extraction/resultmatrix.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "linescoring.h"
#include "simulation/surveysimulator.h"

using namespace geostation;

namespace
{
  struct AerialPair
  {
    std::filesystem::path dir;
    Block block, truth;
    std::vector<TruthRoadLine> roads;
    cv::Mat left, right; //!< luminance
  };

  cv::Mat luminance( const std::filesystem::path &file )
  {
    const RasterImage raster = readRaster( file.string() );
    cv::Mat grey;
    if ( raster.pixels.channels() == 3 )
      cv::cvtColor( raster.pixels, grey, cv::COLOR_RGB2GRAY );
    else
      grey = raster.pixels;
    return grey;
  }

  const AerialPair &aerialPair()
  {
    static const AerialPair pair = []
    {
      AerialPair p;
      p.dir = std::filesystem::temp_directory_path() / ( "geostation-extraction-" + std::to_string( ::getpid() ) );
      SimulationOptions o;
      o.preset = SurveyPreset::AerialStereo;
      o.outputDir = p.dir;
      o.stations = 2;
      o.groundPixelSizeM = 0.5;
      o.seed = 3;
      o.degradation.noiseSigma = 4.0;
      simulateSurvey( o );
      std::atexit( [] { std::error_code ec; std::filesystem::remove_all( std::filesystem::temp_directory_path() / ( "geostation-extraction-" + std::to_string( ::getpid() ) ), ec ); } );
      p.block = Block::load( p.dir / "block.geostation.json" );
      p.truth = Block::load( p.dir / "truth.geostation.json" );
      p.roads = readTruthRoadLines( p.dir / "truth.gpkg" );
      p.left = luminance( p.block.imageFilePath( p.block.images.at( 0 ) ) );
      p.right = luminance( p.block.imageFilePath( p.block.images.at( 1 ) ) );
      return p;
    }();
    return pair;
  }

  //! The truth centre lines projected into an image (x = col, y = row, z = 0), densified to 1 m, clipped to the frame.
  std::vector<std::vector<Eigen::Vector3d>> truthCentreLinesInImage( const AerialPair &pair, int imageIndex )
  {
    const OrientedImage image = pair.truth.orientedImage( pair.truth.images.at( imageIndex ) );
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const TruthRoadLine &line : pair.roads )
    {
      if ( line.kind != "centre" )
        continue;
      std::vector<Eigen::Vector3d> run;
      for ( size_t i = 0; i + 1 < line.vertices.size(); ++i )
      {
        const Eigen::Vector3d a = line.vertices[i], b = line.vertices[i + 1];
        const int n = std::max( 1, static_cast<int>( std::ceil( ( b - a ).norm() ) ) );
        for ( int k = 0; k < n; ++k )
        {
          const GroundProjection g = image.projectGroundToPixel( a + ( b - a ) * ( static_cast<double>( k ) / n ) );
          if ( g.ok() && g.inFrame )
            run.emplace_back( g.pixelInImage.x(), g.pixelInImage.y(), 0.0 );
          else if ( run.size() > 1 )
          {
            out.push_back( run );
            run.clear();
          }
          else
            run.clear();
        }
      }
      if ( run.size() > 1 )
        out.push_back( run );
    }
    return out;
  }

  //! Buffer scores of image-space polylines against image-space truth (pixels).
  BufferScore scoreInImage( const std::vector<std::vector<Eigen::Vector3d>> &result, const std::vector<std::vector<Eigen::Vector3d>> &truth, double bufferPx )
  {
    double truthLength = 0, truthInside = 0, resultLength = 0, resultInside = 0;
    for ( const auto &t : truth )
    {
      truthLength += polylineLength( t );
      double best = 0;
      // within the buffer of any result line (sampled per sample point: take the union by testing each sample against all lines)
      for ( size_t i = 0; i + 1 < t.size(); ++i )
      {
        const double len = ( t[i + 1] - t[i] ).head<2>().norm();
        const Eigen::Vector3d mid = 0.5 * ( t[i] + t[i + 1] );
        for ( const auto &r : result )
          if ( projectOnto( r, mid, true ).distance <= bufferPx )
          {
            best += len;
            break;
          }
      }
      truthInside += best;
    }
    for ( const auto &r : result )
    {
      resultLength += polylineLength( r );
      for ( size_t i = 0; i + 1 < r.size(); ++i )
      {
        const double len = ( r[i + 1] - r[i] ).head<2>().norm();
        const int n = std::max( 1, static_cast<int>( std::ceil( len ) ) );
        for ( int k = 0; k < n; ++k )
        {
          const Eigen::Vector3d p = r[i] + ( k + 0.5 ) / n * ( r[i + 1] - r[i] );
          for ( const auto &t : truth )
            if ( projectOnto( t, p, true ).distance <= bufferPx )
            {
              resultInside += len / n;
              break;
            }
        }
      }
    }
    BufferScore s;
    s.completeness = truthLength > 0 ? truthInside / truthLength : 0;
    s.correctness = resultLength > 0 ? resultInside / resultLength : 0;
    return s;
  }

  std::vector<std::vector<Eigen::Vector3d>> asLines( const std::vector<CompiledPolygon> &polygons )
  {
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const CompiledPolygon &p : polygons )
    {
      std::vector<Eigen::Vector3d> line;
      for ( const Eigen::Vector2d &v : p.pixels )
        line.emplace_back( v.x(), v.y(), 0.0 );
      out.push_back( line );
    }
    return out;
  }

  LineExtractionOptions aerialOptions()
  {
    LineExtractionOptions o;
    o.object.polarity = -1; // asphalt between bright kerbs and shoulders
    o.object.minContrast = 25.0;
    o.object.maxVariation = 14.0;
    o.object.minWidthPx = 6.0;
    o.object.maxWidthPx = 20.0;
    return o;
  }
} // namespace

TEST( RoadExtraction, SingleImageFindsTheRoads )
{
  const AerialPair &pair = aerialPair();
  ResultMatrix matrix( pair.left.cols, pair.left.rows );
  const LineExtractionSummary summary = extractLines( pair.left, matrix, {}, true, aerialOptions() );
  const CompilationSummary compiled = compileMaxLengthPolygons( matrix, "S*+", false );
  const BufferScore score = scoreInImage( asLines( compiled.polygons ), truthCentreLinesInImage( pair, 0 ), 2.0 );
  std::printf( "single image: %d starting points, %d lines, %d rejected; %zu polygons, %zu intersections; completeness %.3f correctness %.3f\n",
               summary.startingPoints, summary.linesStarted, summary.startsRejected, compiled.polygons.size(), compiled.intersections.size(),
               score.completeness, score.correctness );
  std::printf( "  starting points %.3f s, LEM %.3f s (%.0f px), REM %.3f s (%.0f px)\n", summary.startStage.seconds, summary.lemStage.seconds,
               summary.lemStage.linePx, summary.remStage.seconds, summary.remStage.linePx );
  if ( const char *out = std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
  {
    cv::Mat canvas;
    cv::cvtColor( pair.left, canvas, cv::COLOR_GRAY2BGR );
    for ( const auto &t : truthCentreLinesInImage( pair, 0 ) )
      for ( size_t i = 0; i + 1 < t.size(); ++i )
        cv::line( canvas, cv::Point2d( t[i].x() - 0.5, t[i].y() - 0.5 ), cv::Point2d( t[i + 1].x() - 0.5, t[i + 1].y() - 0.5 ), cv::Scalar( 0, 255, 0 ), 1 );
    for ( int r = 0; r < matrix.height(); ++r )
      for ( int c = 0; c < matrix.width(); ++c )
        if ( uint8_t v = matrix.at( c, r ) )
          canvas.at<cv::Vec3b>( r, c ) = v == '+' ? cv::Vec3b( 0, 255, 255 ) : ( v == 'S' ? cv::Vec3b( 255, 255, 255 ) : cv::Vec3b( 0, 0, 255 ) );
    for ( const DeadEnd &d : summary.deadEnds )
      cv::circle( canvas, cv::Point2d( d.state.pixelInImage.x() - 0.5, d.state.pixelInImage.y() - 0.5 ), 4, cv::Scalar( 255, 0, 255 ), 1 );
    cv::imwrite( std::string( out ) + "/single.png", canvas );
    for ( const DeadEnd &d : summary.deadEnds )
      std::printf( "dead end %s at %.1f %.1f dir %.2f %.2f w %.1f c %.1f\n", deadEndKindName( d.kind ).c_str(), d.state.pixelInImage.x(), d.state.pixelInImage.y(),
                   d.state.direction.x(), d.state.direction.y(), d.state.widthPx, d.state.contrast );
  }
  EXPECT_GT( score.completeness, 0.85 );
  EXPECT_GT( score.correctness, 0.90 );
}

TEST( RoadExtraction, DebugLem )
{
  if ( !std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
    GTEST_SKIP();
  const AerialPair &pair = aerialPair();
  ResultMatrix matrix( pair.left.cols, pair.left.rows );
  LineExtractionOptions o = aerialOptions();
  LineState s;
  s.pixelInImage = Eigen::Vector2d( 300.5, 570.0 );
  s.direction = Eigen::Vector2d( 1, 0 );
  s.widthPx = 12;
  s.contrast = 35;
  for ( int k = 0; k < 40; ++k )
  {
    const Eigen::Vector2d pred = s.pixelInImage + lemStepPx( o.lem, s.widthPx ) * s.direction;
    const std::vector<double> profile = sampleCrossProfile( pair.left, pred, s.direction, 25, -1, 4, 3 );
    const auto sections = findCrossSections( profile, 6, 20, 17, 14 );
    for ( double v : profile )
      std::printf( "%.0f ", v );
    std::printf( "\n" );
    std::printf( "at %.1f %.1f w %.1f c %.1f:", pred.x(), pred.y(), s.widthPx, s.contrast );
    for ( const auto &x : sections )
      std::printf( " [off %.1f w %.1f c %.1f v %.1f]", x.offsetPx, x.widthPx, x.contrast, x.variation );
    std::printf( "\n" );
    const auto next = localStep( pair.left, s, o.object, o.lem );
    if ( !next )
    {
      std::printf( "stop\n" );
      break;
    }
    s = *next;
  }
}

TEST( RoadExtraction, DebugRem )
{
  if ( !std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
    GTEST_SKIP();
  const AerialPair &pair = aerialPair();
  LineExtractionOptions o = aerialOptions();
  LineState s;
  s.pixelInImage = Eigen::Vector2d( 320.6, 569.5 );
  s.direction = Eigen::Vector2d( 1, -0.01 ).normalized();
  s.widthPx = 13.1;
  s.contrast = 40.5;
  const AreaOfInterest area = o.rem.areaAhead( s );
  const AreaAnalysisOptions analysis = o.rem.analysis( s, -1 );
  AreaAnalysisOptions raw = analysis;
  raw.relaxationIterations = 0;
  raw.confirmThreshold = 0.0;
  const auto before = analyseArea( pair.left, area, raw, 0.0 );
  const auto lines = analyseArea( pair.left, area, analysis, 0.0 );
  for ( size_t j = 0; j < lines.size(); ++j )
  {
    std::printf( "line %zu:", j );
    for ( const auto &c : before[j] )
      std::printf( " (%.1f %.2f)", c.offsetPx, c.confidence );
    std::printf( "  ->" );
    for ( const auto &c : lines[j] )
      std::printf( " (%.1f %.2f)", c.offsetPx, c.confidence );
    std::printf( "\n" );
  }
  for ( const auto &l : bestChain( lines, area, analysis, 0.0 ) )
    std::printf( "chain %d %.1f %.2f\n", l.line, l.offsetPx, l.confidence );
}

TEST( RoadExtraction, DebugStarts )
{
  if ( !std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
    GTEST_SKIP();
  const AerialPair &pair = aerialPair();
  LineExtractionOptions o = aerialOptions();
  // a column crossing the main road right of the junction
  for ( int col : { 720, 850, 950 } )
  {
    const std::vector<double> profile = sampleCrossProfile( pair.left, Eigen::Vector2d( col + 0.5, 512 ), Eigen::Vector2d( 1, 0 ), 511, -1, 1.0, 3 );
    for ( const CrossSection &s : findCrossSections( profile, 6, 29, 25, 14 ) )
      std::printf( "col %d: row %.1f w %.1f c %.1f v %.1f\n", col, 512 + s.offsetPx, s.widthPx, s.contrast, s.variation );
  }
  const StartingPointSummary starts = findStartingPoints( pair.left, cv::Rect( 0, 0, 1024, 1024 ), o.object, o.start );
  for ( const LineState &s : starts.points )
    std::printf( "start %.1f %.1f dir %.2f %.2f w %.1f c %.1f\n", s.pixelInImage.x(), s.pixelInImage.y(), s.direction.x(), s.direction.y(), s.widthPx, s.contrast );
}
