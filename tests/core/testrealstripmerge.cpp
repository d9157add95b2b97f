/***************************************************************************
  testrealstripmerge.cpp - the road networks of a strip of pairs made from
  a real aerial photograph, merged into one
  -------------------------------------------------------------------------
  aero3.jpg laid out as an orthophoto of 1 m pixels and photographed by
  three vertical photos along a strip (orthophotopair.h: each 20 % of the
  footprint south of the one before), so that the strip's two pairs
  overlap over its roads; each pair extracted with the defaults and the
  networks merged (networkmerge.h) as `geostation-batch extract` merges
  them. Scored on the ground against the three main roads digitised by
  hand (aero3image.h; buffer: the road's half width + 3 m), a pair where
  both its photos see the ground, the merged network over the same area;
  the sea and the forest, where no line may lie. The batch layer's aims:
  under 2 % of the merged network's length doubled, the merged network
  finding at least what each pair alone finds in that pair's area (0.04
  allowed: lines are cut at the pairs' borders), and no line in the
  roadless areas beyond the pairs' own.
 ***************************************************************************/
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aero3image.h"
#include "extraction/networkmerge.h"
#include "extraction/roadnetworkextractor.h"
#include "imagelinescoring.h"
#include "linescoring.h"
#include "matching/matchimage.h"
#include "orthophotopair.h"

using namespace geostation;
using namespace geostation::orthophotopair;

namespace
{
  constexpr int kPhotos = 3;
  constexpr double kBufferM = 3.0;

  struct StripRun
  {
    OrthophotoPair strip;
    std::vector<PairNetwork> pairs;
    NetworkMergeSummary merged;
  };

  //! The strip extracted pair by pair with the defaults, and merged (once for the tests here).
  const StripRun &stripRun( const cv::Mat &image )
  {
    static const StripRun run = [&] {
      StripRun r;
      r.strip = orthophotoStrip( image, 1.0, -0.2, kPhotos );
      for ( int k = 0; k + 1 < kPhotos; ++k )
      {
        const OrientedImage a = r.strip.photo( k ), b = r.strip.photo( k + 1 );
        const RoadNetworkSummary s = extractRoadNetwork( MatchImage( r.strip.grey[k] ), MatchImage( r.strip.grey[k + 1] ), &a, &b, defaultRoadNetworkOptions() );
        PairNetwork pair;
        pair.pair = "P" + std::to_string( k ) + "-P" + std::to_string( k + 1 );
        for ( const NetworkLine &l : s.network.lines )
        {
          PairNetworkLine line;
          for ( const NetworkVertex &v : l.vertices )
            line.points.push_back( v.point );
          line.sigmaM = l.sigmaMaxM();
          pair.lines.push_back( line );
        }
        r.pairs.push_back( pair );
      }
      r.merged = mergeNetworks( r.pairs );
      return r;
    }();
    return run;
  }

  std::vector<PixelPolyline> plan( const std::vector<std::vector<Eigen::Vector3d>> &lines )
  {
    std::vector<PixelPolyline> out;
    for ( const std::vector<Eigen::Vector3d> &l : lines )
    {
      out.emplace_back();
      for ( const Eigen::Vector3d &p : l )
        out.back().push_back( p.head<2>() );
    }
    return out;
  }

  std::vector<std::vector<Eigen::Vector3d>> linesOf( const PairNetwork &pair )
  {
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const PairNetworkLine &l : pair.lines )
      out.push_back( l.points );
    return out;
  }

  std::vector<std::vector<Eigen::Vector3d>> linesOf( const NetworkMergeSummary &merged )
  {
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const MergedNetworkLine &l : merged.lines )
      out.push_back( l.points );
    return out;
  }

  //! The share of the main roads' length, where pair `first` sees them, within their half width + kBufferM of `lines` (ground XY).
  double completenessInPair( const StripRun &run, int first, const std::vector<PixelPolyline> &lines )
  {
    double total = 0.0, found = 0.0;
    for ( const TruthRoad &road : aero3image::aero3MainRoads() )
    {
      PixelPolyline centre;
      for ( const Eigen::Vector2d &p : road.centre )
        centre.push_back( run.strip.orthoToGround( p ).head<2>() );
      alongLines( { centre }, [&]( const Eigen::Vector2d &p, double length ) {
        if ( !run.strip.bothSee( Eigen::Vector3d( p.x(), p.y(), run.strip.groundM ), 20.0, first ) )
          return;
        total += length;
        if ( distanceToLines( p, lines ) <= road.halfWidthPx * run.strip.gsdM + kBufferM )
          found += length;
      } );
    }
    return total > 0.0 ? found / total : 0.0;
  }

  //! The lines' length (XY) in the sea and the forest.
  double lengthWhereNoRoadIs( const StripRun &run, const std::vector<PixelPolyline> &lines )
  {
    std::vector<std::vector<cv::Point2f>> areas;
    for ( const std::vector<cv::Point2f> &area : aero3image::aero3RoadlessAreas() )
    {
      areas.emplace_back();
      for ( const cv::Point2f &p : area )
      {
        const Eigen::Vector3d g = run.strip.orthoToGround( Eigen::Vector2d( p.x, p.y ) );
        areas.back().emplace_back( static_cast<float>( g.x() ), static_cast<float>( g.y() ) );
      }
    }
    return lengthInAreas( lines, areas );
  }
} // namespace

TEST( RealAerialPhotograph, Aero3StripMergedIsOneNetwork )
{
  const cv::Mat image = cv::imread( aero3image::sampleImagePath( "aero3.jpg" ), cv::IMREAD_GRAYSCALE );
  ASSERT_FALSE( image.empty() ) << "aero3.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  const StripRun &run = stripRun( image );
  const std::vector<PixelPolyline> merged = plan( linesOf( run.merged ) );
  std::vector<std::vector<Eigen::Vector3d>> sideBySide;
  double pairsRoadless = 0.0;
  for ( size_t k = 0; k < run.pairs.size(); ++k )
  {
    const std::vector<PixelPolyline> own = plan( linesOf( run.pairs[k] ) );
    const double alone = completenessInPair( run, static_cast<int>( k ), own ), together = completenessInPair( run, static_cast<int>( k ), merged );
    std::printf( "%s: %zu lines, %.0f m; main roads found %.2f alone, %.2f merged; %.0f m in the sea and the forest\n", run.pairs[k].pair.c_str(), own.size(),
                 totalLength( own ), alone, together, lengthWhereNoRoadIs( run, own ) );
    EXPECT_GT( alone, 0.3 ) << run.pairs[k].pair << " finds some of the main roads";
    EXPECT_GE( together, alone - 0.04 ) << run.pairs[k].pair;
    pairsRoadless += lengthWhereNoRoadIs( run, own );
    for ( const std::vector<Eigen::Vector3d> &l : linesOf( run.pairs[k] ) )
      sideBySide.push_back( l );
  }
  const double doubled = doubledShare( linesOf( run.merged ), 2.0, 5.0 ), doubledApart = doubledShare( sideBySide, 2.0, 5.0 );
  std::printf( "merged: %zu lines, %.0f m (%.0f m in, %.0f m dropped as repeats, %d borders joined, %d junctions); %.1f %% of it doubled "
               "(the pairs' lines side by side: %.1f %%); %.0f m in the sea and the forest (the pairs': %.0f m)\n",
               run.merged.lines.size(), totalLength( merged ), run.merged.lengthInM, run.merged.duplicateLengthM, run.merged.bordersJoined, run.merged.junctions,
               100.0 * doubled, 100.0 * doubledApart, lengthWhereNoRoadIs( run, merged ), pairsRoadless );
  EXPECT_GT( run.merged.duplicateLengthM, 0.05 * run.merged.lengthInM ) << "the pairs overlap over the roads: the merge drops what one pair's lines repeat of the other's";
  EXPECT_LT( doubled, 0.02 );
  EXPECT_LE( lengthWhereNoRoadIs( run, merged ), pairsRoadless + 1e-6 );
}
