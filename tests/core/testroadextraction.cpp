// Road-network extraction (core/extraction) against the simulator's truth:
// an aerial stereo pair at 0.5 m ground pixels with three roads (curves,
// two junctions, 6 and 7 m wide), trees and their shadows, fields, image
// noise; and the pieces on hand-made images.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <tuple>
#include <unistd.h>

#include <Eigen/Geometry>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "extraction/coincidentextraction.h"
#include "extraction/crossprofile.h"
#include "extraction/networkintersection.h"
#include "extraction/pairmapping.h"
#include "extraction/roadnetworkextractor.h"
#include "extraction/lineextractor.h"
#include "extraction/resultmatrix.h"
#include "io/block.h"
#include "matching/matchimage.h"
#include "io/rasterfile.h"
#include "aerialpairs.h"
#include "linescoring.h"
#include "networktopology.h"
#include "simulation/surveysimulator.h"

using namespace geostation;
using namespace geostation::testing;

namespace
{
  void drawDebug( const std::string &name, const cv::Mat &grey, const std::vector<CompiledPolygon> &lines, const std::vector<std::vector<Eigen::Vector3d>> &truth )
  {
    const char *out = std::getenv( "GEOSTATION_EXTRACTION_DEBUG" );
    if ( !out )
      return;
    cv::Mat canvas;
    cv::cvtColor( grey, canvas, cv::COLOR_GRAY2BGR );
    for ( const auto &t : truth )
      for ( size_t i = 0; i + 1 < t.size(); ++i )
        cv::line( canvas, cv::Point2d( t[i].x() - 0.5, t[i].y() - 0.5 ), cv::Point2d( t[i + 1].x() - 0.5, t[i + 1].y() - 0.5 ), cv::Scalar( 0, 255, 0 ), 1 );
    for ( const CompiledPolygon &p : lines )
      for ( size_t i = 0; i + 1 < p.pixels.size(); ++i )
        cv::line( canvas, cv::Point2d( p.pixels[i].x() - 0.5, p.pixels[i].y() - 0.5 ), cv::Point2d( p.pixels[i + 1].x() - 0.5, p.pixels[i + 1].y() - 0.5 ), cv::Scalar( 0, 0, 255 ), 1 );
    cv::imwrite( std::string( out ) + "/" + name + ".png", canvas );
  }
  struct PairEvaluation
  {
    BufferScore a, b, verifiedAll, unverifiedAll, onGround;
    int junctions = 0, junctionsFound = 0, vertices = 0, within2Sigma = 0;
    double junctionOffPx = 0.0; //!< the intersections found within 3 m: their mean distance to the truth in image A
    size_t intersectionsA = 0;
    TopologyScore topology; //!< image A against the truth centre lines seen in both images
  };

  //! Runs the coincident extraction and the 3-D lines on a pair and scores them against the truth.
  PairEvaluation evaluate( const AerialPair &pair, const LineExtractionOptions &extraction, const std::string &name, double junctionReachM )
  {
    PairEvaluation e;
  const OrientedPairMapping mapping( pair.block.orientedImage( pair.block.images.at( 0 ) ), pair.block.orientedImage( pair.block.images.at( 1 ) ), meanRoadHeight( pair ) );
  CoincidentExtractionOptions options;
  options.extraction = extraction;
  const CoincidentExtractionSummary verified = extractCoincident( pair.left, pair.right, mapping, options );
  options.verify = false;
  const CoincidentExtractionSummary single = extractCoincident( pair.left, pair.right, mapping, options );
  const auto truthA = truthCentreLinesInImage( pair, 0, true ), truthB = truthCentreLinesInImage( pair, 1, true );
  const BufferScore a = scoreInImage( asLines( verified.linesA ), truthA, 2.0 );
  const BufferScore b = scoreInImage( asLines( verified.linesB ), truthB, 2.0 );
  // correctness against every truth line in the image (lines outside the overlap are right, if unverifiable)
  const auto fullTruthA = truthCentreLinesInImage( pair, 0 );
  const BufferScore unverified = scoreInImage( asLines( single.linesA ), fullTruthA, 2.0 );
  const BufferScore verifiedFull = scoreInImage( asLines( verified.linesA ), fullTruthA, 2.0 );

  for ( const RoundReport &r : verified.rounds )
    std::printf( "round %d in %s: %d starts, %d lines, %d continued; %d polygons: %d wholly, %d partly, %d rejected; %.0f px extracted, %.0f accepted; %.2f s\n",
                 r.round, r.image.c_str(), r.startingPoints, r.linesStarted, r.continued, r.polygons, r.wholly, r.partly, r.rejected, r.extractedPx, r.acceptedPx, r.seconds );
  std::printf( "coincident: A %.3f / %.3f, B %.3f / %.3f; correctness with verification %.3f, without %.3f; %d bridged, %d spurs pruned, %zu + %zu intersections\n", a.completeness, a.correctness,
               b.completeness, b.correctness, verifiedFull.correctness, unverified.correctness, verified.bridged, verified.pruned, verified.intersectionsA.size(), verified.intersectionsB.size() );
  // junctions: where a truth centre line ends within 6 m of another (its centre line is clipped at the other road's edge)
  std::vector<Eigen::Vector2d> junctions;
  {
    std::vector<std::vector<Eigen::Vector3d>> centres;
    for ( const TruthRoadLine &l : pair.roads )
      if ( l.kind == "centre" )
        centres.push_back( l.vertices );
    const OrientedImage ta = pair.truth.orientedImage( pair.truth.images.at( 0 ) ), tb = pair.truth.orientedImage( pair.truth.images.at( 1 ) );
    for ( size_t i = 0; i < centres.size(); ++i )
      for ( const Eigen::Vector3d &end : { centres[i].front(), centres[i].back() } )
        for ( size_t k = 0; k < centres.size(); ++k )
        {
          if ( k == i )
            continue;
          const PolylineProjection on = projectOnto( centres[k], end, true );
          if ( on.distance > junctionReachM )
            continue;
          const GroundProjection ga = ta.projectGroundToPixel( on.point ), gb = tb.projectGroundToPixel( on.point );
          bool known = false;
          for ( const Eigen::Vector2d &j : junctions )
            known = known || ( j - ga.pixelInImage ).norm() < 6.0; // both ends of a crossing road give the same junction
          if ( ga.ok() && gb.ok() && ga.inFrame && gb.inFrame && !known )
            junctions.push_back( ga.pixelInImage );
        }
  }
  // and where two centre lines cross
  {
    std::vector<std::vector<Eigen::Vector3d>> centres;
    for ( const TruthRoadLine &l : pair.roads )
      if ( l.kind == "centre" )
        centres.push_back( l.vertices );
    const OrientedImage ta = pair.truth.orientedImage( pair.truth.images.at( 0 ) ), tb = pair.truth.orientedImage( pair.truth.images.at( 1 ) );
    for ( size_t i = 0; i < centres.size(); ++i )
      for ( size_t k = i + 1; k < centres.size(); ++k )
        for ( size_t u = 0; u + 1 < centres[i].size(); ++u )
          for ( size_t v = 0; v + 1 < centres[k].size(); ++v )
          {
            const Eigen::Vector2d p = centres[i][u].head<2>(), r = centres[i][u + 1].head<2>() - p, q = centres[k][v].head<2>(), t = centres[k][v + 1].head<2>() - q;
            const double den = r.x() * t.y() - r.y() * t.x();
            if ( std::abs( den ) < 1e-9 )
              continue;
            const double a = ( ( q - p ).x() * t.y() - ( q - p ).y() * t.x() ) / den, b = ( ( q - p ).x() * r.y() - ( q - p ).y() * r.x() ) / den;
            if ( a < 0 || a > 1 || b < 0 || b > 1 )
              continue;
            const Eigen::Vector3d x = centres[i][u] + a * ( centres[i][u + 1] - centres[i][u] );
            const GroundProjection ga = ta.projectGroundToPixel( x ), gb = tb.projectGroundToPixel( x );
            bool known = false;
            for ( const Eigen::Vector2d &j : junctions )
              known = known || ( j - ga.pixelInImage ).norm() < 6.0;
            if ( ga.ok() && gb.ok() && ga.inFrame && gb.inFrame && !known )
              junctions.push_back( ga.pixelInImage );
          }
  }
  int junctionsFound = 0;
  double junctionOffSum = 0.0;
  for ( const Eigen::Vector2d &j : junctions )
  {
    double nearest = 1e9;
    for ( const Eigen::Vector2d &x : verified.intersectionsA )
      nearest = std::min( nearest, ( x - j ).norm() );
    if ( nearest <= 6.0 ) // 3 m
    {
      ++junctionsFound;
      junctionOffSum += nearest;
    }
  }
  std::printf( "junctions: %d of %d within 3 m (%.2f px off on average); %zu intersections found in A\n", junctionsFound, static_cast<int>( junctions.size() ),
               junctionsFound > 0 ? junctionOffSum / junctionsFound : 0.0, verified.intersectionsA.size() );
  if ( std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
  {
    for ( const Eigen::Vector2d &j : junctions )
      std::printf( "  truth junction %.1f %.1f\n", j.x(), j.y() );
    for ( const Eigen::Vector2d &x : verified.intersectionsA )
      std::printf( "  found %.1f %.1f\n", x.x(), x.y() );
  }
  e.junctions = static_cast<int>( junctions.size() );
  e.junctionsFound = junctionsFound;
  e.junctionOffPx = junctionsFound > 0 ? junctionOffSum / junctionsFound : 0.0;
  // topology: truth centre lines end up to the junction reach from the road they join (0.5 m pixels);
  // extracted lines are joined where compilation placed the intersection (within 2 px); control points every 10 m, found within 2 m
  e.topology = averagePathLengthSimilarity( truthA, 2.0 * junctionReachM, asLines( verified.linesA ), 2.0, 20.0, 4.0 );
  std::printf( "topology (average path-length similarity): %.3f (truth -> extracted %.3f, extracted -> truth %.3f; %d pairs)\n", e.topology.apls,
               e.topology.truthToResult, e.topology.resultToTruth, e.topology.pairs );
  e.intersectionsA = verified.intersectionsA.size();
  drawDebug( name + "A", pair.left, verified.linesA, truthA );
  if ( std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
    for ( const DeadEnd &d : verified.deadEndsA )
      std::printf( "open end in A at %.1f %.1f towards %.2f %.2f\n", d.state.pixelInImage.x(), d.state.pixelInImage.y(), d.state.direction.x(), d.state.direction.y() );
  drawDebug( name + "B", pair.right, verified.linesB, truthB );
  e.a = a;
  e.b = b;
  e.verifiedAll = verifiedFull;
  e.unverifiedAll = unverified;

  // 3-D: on the ground against the truth centre lines (0.5 m buffer), and the sigmas
  const NetworkIntersectionSummary network = intersectNetwork( mapping, verified.linesA, verified.linesB, MatchImage( pair.left ), MatchImage( pair.right ) );
  std::vector<std::vector<Eigen::Vector3d>> ground, truthGround;
  int within2Sigma = 0, vertices = 0;
  std::vector<double> planDistances;
  std::vector<Eigen::Vector3d> allTruth;
  for ( const TruthRoadLine &l : pair.roads )
    if ( l.kind == "centre" )
      truthGround.push_back( l.vertices );
  for ( const NetworkLine &line : network.lines )
  {
    std::vector<Eigen::Vector3d> g;
    for ( const NetworkVertex &v : line.vertices )
    {
      g.push_back( v.point );
      PolylineProjection nearest;
      for ( const auto &t : truthGround )
      {
        const PolylineProjection p = projectOnto( t, v.point, true );
        if ( p.distance < nearest.distance )
          nearest = p;
      }
      const double dz = std::abs( v.point.z() - nearest.point.z() );
      const double sigmaPlan = std::hypot( v.sigmaM.x(), v.sigmaM.y() );
      planDistances.push_back( nearest.distance );
      ++vertices;
      within2Sigma += dz <= 2.0 * v.sigmaM.z() && nearest.distance <= 2.0 * sigmaPlan;
      if ( std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) && !( dz <= 2.0 * v.sigmaM.z() && nearest.distance <= 2.0 * sigmaPlan ) )
        std::printf( "  off: %s A %.1f %.1f dz %.2f sz %.2f plan %.2f sp %.2f\n", v.method.c_str(), v.inA.x(), v.inA.y(), dz, v.sigmaM.z(), nearest.distance, sigmaPlan );
    }
    ground.push_back( g );
  }
  // truth on the ground where both images see it
  std::vector<std::vector<Eigen::Vector3d>> truthStereo;
  const OrientedImage ta = pair.truth.orientedImage( pair.truth.images.at( 0 ) ), tb = pair.truth.orientedImage( pair.truth.images.at( 1 ) );
  for ( const auto &t : truthGround )
  {
    std::vector<Eigen::Vector3d> run;
    for ( const Eigen::Vector3d &v : t )
    {
      const GroundProjection ga = ta.projectGroundToPixel( v ), gb = tb.projectGroundToPixel( v );
      const bool seen = ga.ok() && gb.ok() && ga.pixelInImage.minCoeff() > 10 && gb.pixelInImage.minCoeff() > 10 && ga.pixelInImage.maxCoeff() < 1014 && gb.pixelInImage.maxCoeff() < 1014;
      extendRun( truthStereo, run, seen, v );
    }
    if ( run.size() > 1 )
      truthStereo.push_back( run );
  }
  const BufferScore onGround = scoreInImage( ground, truthStereo, 0.5 );
  std::sort( planDistances.begin(), planDistances.end() );
  if ( !planDistances.empty() )
    std::printf( "3-D plan distance to the truth: median %.2f m, 90 %% %.2f m\n", planDistances[planDistances.size() / 2], planDistances[planDistances.size() * 9 / 10] );
  std::printf( "3-D: %d vertices, %d by line crossing, %d by area matching, %d unmatched; on the ground %.3f / %.3f (0.5 m); %.1f %% within 2 sigma\n",
               network.vertices, network.byCrossing, network.byArea, network.unmatched, onGround.completeness, onGround.correctness, 100.0 * within2Sigma / std::max( 1, vertices ) );
  e.onGround = onGround;
  e.vertices = vertices;
  e.within2Sigma = within2Sigma;
  return e;
  }


} // namespace

TEST( RoadExtraction, CoincidentExtractionVerifiesInThePartner )
{
  const PairEvaluation e = evaluate( aerialPair(), aerialOptions(), "coincident", 6.0 );
  // image space, buffer 2 px, where both images see the roads
  EXPECT_GT( e.a.completeness, 0.90 );
  EXPECT_GT( e.a.correctness, 0.95 );
  EXPECT_GT( e.b.completeness, 0.90 );
  EXPECT_GT( e.b.correctness, 0.95 );
  // verification earns its keep
  EXPECT_GT( e.verifiedAll.correctness, e.unverifiedAll.correctness );
  EXPECT_EQ( e.junctions, 2 );
  EXPECT_EQ( e.junctionsFound, 2 );
  // where their branches, moved onto their bands, cross (measured 1.35 px off; 1.75 px where compilation put them)
  EXPECT_LT( e.junctionOffPx, 1.6 );
  // the network's topology against the truth graph (average path-length similarity)
  EXPECT_GT( e.topology.apls, 0.93 );
  // on the ground, 0.5 m (one pixel): the aims are 0.85 / 0.95 and a quality of 0.80 (measured 0.945 / 0.980;
  // before the lines were moved onto their band's centre 0.876 / 0.893); sigmas honest: 98.4 % within 2 sigma
  EXPECT_GT( e.onGround.completeness, 0.90 );
  EXPECT_GT( e.onGround.correctness, 0.95 );
  EXPECT_GT( quality( e.onGround ), 0.85 );
  EXPECT_GE( e.within2Sigma, 0.93 * e.vertices );
}

TEST( RoadExtraction, ANetworkBuiltDifferently )
{
  // widths from 7 to 14 m (14 to 28 px), two crossings, a T, a bend: a scene laid out by hand, not by the preset
  LineExtractionOptions options = aerialOptions();
  options.object.maxWidthPx = 32.0;
  const PairEvaluation e = evaluate( townPair(), options, "town", 9.0 );
  EXPECT_GT( e.a.completeness, 0.90 );
  EXPECT_GT( e.b.completeness, 0.90 );
  // below the aim of 0.95: the shadow strip along the dual carriageway's north edge is a real band in both images, and verification keeps it
  EXPECT_GT( e.a.correctness, 0.90 );
  EXPECT_GT( e.b.correctness, 0.90 );
  EXPECT_EQ( e.junctions, 3 );
  EXPECT_EQ( e.junctionsFound, 3 );
  // the crossings and the T where their branches, moved, cross: measured 0.34 px off (2.22 px where compilation put them)
  EXPECT_LT( e.junctionOffPx, 1.0 );
  EXPECT_GT( e.topology.apls, 0.88 );
  EXPECT_GE( e.within2Sigma, 0.8 * e.vertices );
}

// The simulator's pairs with extract_roads' defaults (either polarity, 3-30 m, the contrast 1.8 x the texture),
// each scored by the buffer method within 1.5 m where both photos see the ground (also within 3.5 m, and over
// the whole left image as earlier figures were): the preset's roads, a town with a dual carriageway, the
// preset's layout with seed 7. Known failing (the aims are completeness 0.85 and correctness 0.90).
TEST( RoadExtraction, DISABLED_DefaultsOnTheSimulatorsPairs )
{
  for ( const auto &[name, pair] : { std::pair<const char *, const AerialPair *>( "preset", &aerialPair() ), { "town", &townPair() }, { "seed 7", &seedPair( 7 ) } } )
  {
    const OrientedImage a = pair->block.orientedImage( pair->block.images.at( 0 ) ), b = pair->block.orientedImage( pair->block.images.at( 1 ) );
    const RoadNetworkSummary s = extractRoadNetwork( MatchImage( pair->left ), MatchImage( pair->right ), &a, &b, defaultRoadNetworkOptions() );
    const std::vector<std::vector<Eigen::Vector3d>> lines = asLines( s.extraction.linesA ), truth = truthCentreLinesInImage( *pair, 0, true );
    const BufferScore near = scoreInImage( lines, truth, 3.0 ), wide = scoreInImage( lines, truth, 7.0 );
    const BufferScore whole = scoreInImage( lines, truthCentreLinesInImage( *pair, 0 ), 3.0 );
    // a road found twice: lines within 2 m of each other and about parallel, away from their ends (5 m)
    const double doubled = doubledShare( lines, 4.0, 10.0 );
    std::printf( "%s pair with the defaults, where both photos see: completeness %.2f, correctness %.2f (within 3.5 m: %.2f, %.2f; over the whole left "
                 "image %.2f, %.2f; contrast %.0f); %.1f %% of the lines' length doubled\n",
                 name, near.completeness, near.correctness, wide.completeness, wide.correctness, whole.completeness, whole.correctness, s.minContrast, 100 * doubled );
    drawDebug( std::string( "defaults_" ) + name, pair->left, s.extraction.linesA, truth );
    EXPECT_GE( near.completeness, 0.85 ) << name;
    EXPECT_GE( near.correctness, 0.90 ) << name;
    EXPECT_LT( doubled, 0.02 ) << name;
  }
}

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
  EXPECT_GT( score.completeness, 0.75 ); // the whole image: including roads the partner does not see
  EXPECT_GT( score.correctness, 0.95 );
}

TEST( RoadExtraction, CompilationSplitsAtIntersections )
{
  ResultMatrix matrix( 200, 200 );
  matrix.drawPolyline( { Eigen::Vector2d( 10.5, 100.5 ), Eigen::Vector2d( 190.5, 80.5 ) }, ResultMatrix::kLocal );
  matrix.drawPolyline( { Eigen::Vector2d( 100.5, 190.5 ), Eigen::Vector2d( 99.5, 91.5 ) }, ResultMatrix::kRegional ); // a T onto the first line
  CompilationSummary t = compileMaxLengthPolygons( matrix, "*+", false );
  ASSERT_EQ( t.intersections.size(), 1u );
  EXPECT_EQ( t.polygons.size(), 3u );
  EXPECT_NEAR( t.intersections[0].x(), 100.0, 2.0 );
  EXPECT_NEAR( t.intersections[0].y(), 90.5, 2.0 );
  double length = 0;
  for ( const CompiledPolygon &p : t.polygons )
    length += polylineLength( p.pixels );
  EXPECT_NEAR( length, std::hypot( 180, 20 ) + 99, 8.0 );
  // a crossing: four polygons from one node
  matrix.drawPolyline( { Eigen::Vector2d( 100.5, 91.5 ), Eigen::Vector2d( 105.5, 10.5 ) }, ResultMatrix::kLocal );
  const CompilationSummary x = compileMaxLengthPolygons( matrix, "*+", true );
  EXPECT_EQ( x.intersections.size(), 1u );
  EXPECT_EQ( x.polygons.size(), 4u );
  EXPECT_EQ( matrix.count( "*+" ), 0 ); // erased
  // a T with a gap of 8 px is closed by the kite search from the open end
  ResultMatrix gap( 200, 200 );
  gap.drawPolyline( { Eigen::Vector2d( 10.5, 100.5 ), Eigen::Vector2d( 190.5, 100.5 ) }, ResultMatrix::kInternal );
  gap.drawPolyline( { Eigen::Vector2d( 60.5, 190.5 ), Eigen::Vector2d( 62.5, 109.5 ) }, ResultMatrix::kExternal );
  EXPECT_EQ( compileMaxLengthPolygons( gap, "IE", false ).intersections.size(), 0u );
  EXPECT_EQ( bridgeOpenEnds( gap, "IE", ResultMatrix::kInternal, 20, 12 ), 1 );
  const CompilationSummary closed = compileMaxLengthPolygons( gap, "IE", false );
  EXPECT_EQ( closed.intersections.size(), 1u );
  EXPECT_EQ( closed.polygons.size(), 3u );
}

TEST( RoadExtraction, PairMappingsFromControlPoints )
{
  // a known projective map and a smooth non-planar one
  Eigen::Matrix3d h;
  h << 1.02, 0.05, -30, -0.03, 0.98, 12, 2e-5, -1e-5, 1;
  const auto project = [&]( const Eigen::Vector2d &p ) { const Eigen::Vector3d q = h * p.homogeneous(); return Eigen::Vector2d( q.head<2>() / q.z() ); };
  std::vector<ControlPair> pairs;
  for ( const Eigen::Vector2d &p : { Eigen::Vector2d( 50, 60 ), Eigen::Vector2d( 900, 80 ), Eigen::Vector2d( 880, 950 ), Eigen::Vector2d( 70, 900 ), Eigen::Vector2d( 500, 480 ) } )
    pairs.push_back( { "p", p, project( p ) } );
  RegistrationReport report;
  const ProjectiveMapping projective = ProjectiveMapping::fit( pairs, &report );
  EXPECT_LT( report.maxPx, 1e-6 );
  EXPECT_LT( ( *projective.toB( Eigen::Vector2d( 300, 700 ) ) - project( Eigen::Vector2d( 300, 700 ) ) ).norm(), 1e-6 );
  EXPECT_LT( ( *projective.toA( project( Eigen::Vector2d( 300, 700 ) ) ) - Eigen::Vector2d( 300, 700 ) ).norm(), 1e-6 );

  // terrain relief: a projective map leaves residuals, the multiquadric interpolates them
  const auto relief = [&]( const Eigen::Vector2d &p ) { return Eigen::Vector2d( project( p ) + Eigen::Vector2d( 6.0 * std::sin( p.x() / 150.0 ) * std::cos( p.y() / 200.0 ), 0.0 ) ); };
  std::vector<ControlPair> grid;
  for ( int r = 0; r < 6; ++r )
    for ( int c = 0; c < 6; ++c )
    {
      const Eigen::Vector2d p( 40 + 180 * c + 7 * r, 50 + 175 * r + 5 * c );
      grid.push_back( { "g", p, relief( p ) } );
    }
  RegistrationReport projectiveReport, multiquadricReport;
  const ProjectiveMapping plane = ProjectiveMapping::fit( grid, &projectiveReport );
  const MultiquadricMapping multiquadric = MultiquadricMapping::fit( grid, 1.0, &multiquadricReport );
  double worstPlane = 0, worstMq = 0;
  for ( double x = 100; x < 900; x += 97 )
    for ( double y = 100; y < 900; y += 89 )
    {
      const Eigen::Vector2d p( x, y );
      worstPlane = std::max( worstPlane, ( *plane.toB( p ) - relief( p ) ).norm() );
      worstMq = std::max( worstMq, ( *multiquadric.toB( p ) - relief( p ) ).norm() );
      EXPECT_LT( ( *multiquadric.toA( relief( p ) ) - p ).norm(), 2.0 );
    }
  std::printf( "misregistration: projective %.2f px (control rms %.2f), multiquadric %.2f px (leave-one-out rms %.2f)\n", worstPlane, projectiveReport.rmsPx,
               worstMq, multiquadricReport.rmsPx );
  EXPECT_GT( worstPlane, 4.0 );
  EXPECT_LT( worstMq, 1.5 );
  EXPECT_GT( projectiveReport.rmsPx, 2.0 );
  EXPECT_LT( multiquadricReport.rmsPx, 2.0 );
  // the misregistration to expect away from the points, and the verification's search from it
  std::printf( "expected misregistration: projective %.2f px, multiquadric %.2f px\n", projectiveReport.expectedPx, multiquadricReport.expectedPx );
  EXPECT_GT( projectiveReport.expectedPx, 0.9 * worstPlane );
  EXPECT_GT( multiquadricReport.expectedPx, worstMq ); // leave-one-out at the grid's edge: on the safe side
  // the search covers the misregistration the mappings actually have between the points
  EXPECT_GE( verificationSearchPx( projectiveReport, 100.0 ), worstPlane + 2.0 );
  EXPECT_GE( verificationSearchPx( multiquadricReport, 100.0 ), worstMq + 2.0 );
  EXPECT_LT( report.expectedPx, 1e-5 ); // five exact pairs
  RegistrationReport four;
  ProjectiveMapping::fit( { pairs[0], pairs[1], pairs[2], pairs[3] }, &four );
  EXPECT_TRUE( std::isnan( four.expectedPx ) ); // no redundancy: the points cannot tell
  EXPECT_DOUBLE_EQ( verificationSearchPx( four, 12.0 ), 12.0 );
  EXPECT_DOUBLE_EQ( verificationSearchPx( report, 12.0 ), 3.0 );
  EXPECT_DOUBLE_EQ( verificationSearchPx( multiquadricReport, 12.0 ), std::clamp( 2.0 * multiquadricReport.expectedPx + 2.0, 3.0, 12.0 ) );
  EXPECT_DOUBLE_EQ( verificationSearchPx( projectiveReport, 12.0 ), 12.0 );
  EXPECT_DOUBLE_EQ( verificationSearchPx( report, 2.0 ), 2.0 ); // never wider than asked for

  // too few or collinear points: one clear sentence
  const std::vector<ControlPair> three( pairs.begin(), pairs.begin() + 3 );
  EXPECT_THROW( ProjectiveMapping::fit( three ), std::invalid_argument );
  std::vector<ControlPair> line;
  for ( int i = 0; i < 6; ++i )
    line.push_back( { "l", Eigen::Vector2d( 10 + 100 * i, 20 + 50 * i ), Eigen::Vector2d( 15 + 100 * i, 22 + 50 * i ) } );
  try
  {
    MultiquadricMapping::fit( line );
    FAIL() << "collinear points accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "lie on a line" ), std::string::npos ) << e.what();
  }
  EXPECT_THROW( ProjectiveMapping::fit( line ), std::invalid_argument );
  EXPECT_THROW( MultiquadricMapping::fit( { pairs[0], pairs[1] } ), std::invalid_argument );
}

TEST( RoadExtraction, EmptyAndBadInput )
{
  // no road at all: nothing extracted, not an error
  cv::Mat fields( 400, 400, CV_8UC1 );
  cv::randn( fields, 90, 12 );
  ResultMatrix matrix( 400, 400 );
  LineExtractionOptions options = aerialOptions();
  const LineExtractionSummary none = extractLines( fields, matrix, {}, true, options );
  EXPECT_EQ( none.linesStarted, 0 );
  EXPECT_EQ( matrix.count( "S*+" ), 0 );
  // options and images checked
  options.object.minWidthPx = 30;
  options.object.maxWidthPx = 10;
  EXPECT_THROW( extractLines( fields, matrix, {}, true, options ), std::invalid_argument );
  EXPECT_THROW( extractLines( cv::Mat( 400, 400, CV_8UC3 ), matrix, {}, true, aerialOptions() ), std::invalid_argument );
  ResultMatrix small( 100, 100 );
  EXPECT_THROW( extractLines( fields, small, {}, true, aerialOptions() ), std::invalid_argument );

  // a pair that does not overlap: one sentence
  const AerialPair &pair = aerialPair();
  const OrientedImage a = pair.block.orientedImage( pair.block.images.at( 0 ) );
  ExteriorOrientation away = pair.block.orientedImage( pair.block.images.at( 1 ) ).exterior();
  away.projectionCentre.x() += 5000.0;
  const OrientedImage b = a.withExterior( away );
  RoadNetworkOptions network;
  network.coincident.extraction = aerialOptions();
  network.meanHeightM = meanRoadHeight( pair );
  try
  {
    extractRoadNetwork( MatchImage( pair.left ), MatchImage( pair.right ), &a, &b, network );
    FAIL() << "a pair without overlap accepted";
  }
  catch ( const std::invalid_argument &e )
  {
    EXPECT_NE( std::string( e.what() ).find( "do not overlap" ), std::string::npos ) << e.what();
  }
}

TEST( RoadExtraction, FiveMorePairs )
{
  // the preset's layout with other terrain, trees, shadows, cars and noise (seeds): the spread of the numbers
  double completeness = 0, correctness = 0, worstCompleteness = 1, worstCorrectness = 1;
  int junctions = 0, found = 0;
  double topology = 0.0, junctionOffSum = 0.0;
  double groundCompleteness = 0.0, groundCorrectness = 0.0, worstGroundCorrectness = 1.0, worstGroundQuality = 1.0;
  int vertices = 0, within2Sigma = 0;
  const std::vector<uint32_t> seeds { 1, 2, 4, 5, 6 };
  for ( const uint32_t seed : seeds )
  {
    const AerialPair &pair = seedPair( seed );
    const PairEvaluation e = evaluate( pair, aerialOptions(), "seed" + std::to_string( seed ), 6.0 );
    completeness += e.a.completeness / seeds.size();
    correctness += e.a.correctness / seeds.size();
    worstCompleteness = std::min( worstCompleteness, e.a.completeness );
    worstCorrectness = std::min( worstCorrectness, e.a.correctness );
    junctions += e.junctions;
    found += e.junctionsFound;
    junctionOffSum += e.junctionOffPx * e.junctionsFound;
    topology += e.topology.apls;
    groundCompleteness += e.onGround.completeness / seeds.size();
    groundCorrectness += e.onGround.correctness / seeds.size();
    worstGroundCorrectness = std::min( worstGroundCorrectness, e.onGround.correctness );
    worstGroundQuality = std::min( worstGroundQuality, quality( e.onGround ) );
    vertices += e.vertices;
    within2Sigma += e.within2Sigma;
  }
  std::printf( "five pairs: completeness %.3f (worst %.3f), correctness %.3f (worst %.3f), junctions %d of %d within 3 m (%.2f px off on average), topology %.3f on average; "
               "on the ground %.3f / %.3f (worst correctness %.3f, worst quality %.3f), %d of %d 3-D vertices within 2 sigma\n",
               completeness, worstCompleteness, correctness, worstCorrectness, found, junctions, found > 0 ? junctionOffSum / found : 0.0, topology / seeds.size(),
               groundCompleteness, groundCorrectness,
               worstGroundCorrectness, worstGroundQuality, within2Sigma, vertices );
  EXPECT_GT( completeness, 0.90 );
  EXPECT_GT( correctness, 0.95 );
  EXPECT_GT( worstCompleteness, 0.80 );
  EXPECT_GT( worstCorrectness, 0.95 );
  // the aim: 90 % of the junctions within 3 m (a road's stretch into a junction in a tree's shadow is joined along
  // the band the image shows; one of ten is still missed)
  EXPECT_GE( found, 0.9 * junctions );
  // ... where their branches, moved, cross: measured 1.16 px off on average (1.77 px where compilation put them)
  EXPECT_LT( junctionOffSum / std::max( 1, found ), 1.5 );
  EXPECT_GT( topology / seeds.size(), 0.85 );
  // on the ground, 0.5 m: the aims 0.85 / 0.95, quality 0.80 (measured 0.905 / 0.981 on average, worst correctness
  // 0.962, worst quality 0.84; 97 % of the 3-D vertices within 2 sigma)
  EXPECT_GT( groundCompleteness, 0.85 );
  EXPECT_GT( groundCorrectness, 0.95 );
  EXPECT_GT( worstGroundCorrectness, 0.93 );
  EXPECT_GT( worstGroundQuality, 0.80 );
  EXPECT_GE( within2Sigma, 0.9 * vertices );
}

TEST( RoadExtraction, TopologyMeasureSeesGapsAndFalseLinks )
{
  // a T junction: a 400 px main road and a 200 px side road ending 8 px short of it (as truth centre lines do)
  const std::vector<std::vector<Eigen::Vector3d>> truth { { { 0, 100, 0 }, { 400, 100, 0 } }, { { 200, 108, 0 }, { 200, 308, 0 } } };
  const auto score = [&]( const std::vector<std::vector<Eigen::Vector3d>> &result ) { return averagePathLengthSimilarity( truth, 10.0, result, 2.0, 20.0, 4.0 ); };
  // the same network, joined at the junction: 1
  const TopologyScore same = score( { { { 0, 100, 0 }, { 200, 100, 0 } }, { { 200, 100, 0 }, { 400, 100, 0 } }, { { 200, 100, 0 }, { 200, 308, 0 } } } );
  EXPECT_NEAR( same.apls, 1.0, 1e-9 );
  EXPECT_GT( same.pairs, 100 );
  // the side road found but not joined (a junction lost): every path into it is broken
  const TopologyScore lostJunction = score( { { { 0, 100, 0 }, { 400, 100, 0 } }, { { 200, 130, 0 }, { 200, 308, 0 } } } );
  EXPECT_LT( lostJunction.truthToResult, 0.75 );
  EXPECT_GT( lostJunction.resultToTruth, lostJunction.truthToResult );
  // a gap of 20 px in the main road: paths across it are lost, those on either side kept
  const TopologyScore gap = score( { { { 0, 100, 0 }, { 140, 100, 0 } }, { { 160, 100, 0 }, { 400, 100, 0 } }, { { 200, 100, 0 }, { 200, 308, 0 } } } );
  EXPECT_LT( gap.truthToResult, 0.8 );
  EXPECT_GT( gap.truthToResult, lostJunction.truthToResult - 0.3 );
  // a false road joined to the network (a field track taken for a road): extracted -> truth falls, truth -> extracted stays 1;
  // (an isolated false piece costs less: only its own pairs count, as in APLS)
  const TopologyScore falseRoad = score( { { { 0, 100, 0 }, { 400, 100, 0 } }, { { 200, 100, 0 }, { 200, 308, 0 } }, { { 300, 100, 0 }, { 300, 250, 0 } } } );
  EXPECT_NEAR( falseRoad.truthToResult, 1.0, 1e-9 );
  EXPECT_LT( falseRoad.resultToTruth, 0.8 );
  // a false short cut between two roads makes paths too short
  const TopologyScore shortCut = score( { { { 0, 100, 0 }, { 400, 100, 0 } }, { { 200, 100, 0 }, { 200, 308, 0 } }, { { 0, 100, 0 }, { 200, 308, 0 } } } );
  EXPECT_LT( shortCut.resultToTruth, 0.9 );
}
