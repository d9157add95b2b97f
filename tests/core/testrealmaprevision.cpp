/***************************************************************************
  testrealmaprevision.cpp - an old road map held against a pair made from a
  real 10 m image of a city
  -------------------------------------------------------------------------
  Central Chicago (chicagoimage.h), with a map made from the roads
  digitised on it and changed on purpose: Michigan Avenue, Lake Shore
  Drive and the street at row 307 as they are; Roosevelt Road mapped 40 m
  (4 px) north of where it runs; the Eisenhower expressway left out; a
  road mapped diagonally across the blocks where none runs. With the
  defaults. The aims are those of the painted and simulated scenes:
  unchanged roads confirmed along >= 95 %, the shifted one moved along
  >= 90 % with its new course within 1 m RMS (here: within a ground pixel),
  the road not there not found along >= 90 %, the road left out among the
  new roads along >= 90 %.
 ***************************************************************************/
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "chicagoimage.h"
#include "matching/matchimage.h"
#include "orthophotopair.h"
#include "revision/maprevision.h"
#include "revisionlengths.h"

using namespace geostation;
using geostation::testing::lengthOf;
using namespace geostation::chicagoimage;
using namespace geostation::orthophotopair;

namespace
{
  const TruthRoad &roadNamed( const std::string &name )
  {
    static const std::vector<TruthRoad> roads = chicagoMainRoads();
    return *std::find_if( roads.begin(), roads.end(), [&]( const TruthRoad &r ) { return r.name == name; } );
  }

  //! The road's course on the ground (x, y, no height), moved `northM` north.
  std::vector<Eigen::Vector2d> groundCourse( const OrthophotoPair &pair, const PixelPolyline &orthoLine, double northM = 0.0 )
  {
    std::vector<Eigen::Vector2d> out;
    for ( const Eigen::Vector2d &p : orthoLine )
      out.push_back( pair.orthoToGround( p ).head<2>() + Eigen::Vector2d( 0.0, northM ) );
    return out;
  }

  MapRoad mapRoad( const std::vector<Eigen::Vector2d> &xy )
  {
    MapRoad road;
    for ( const Eigen::Vector2d &p : xy )
      road.vertices.emplace_back( p.x(), p.y(), std::nan( "" ) );
    return road;
  }

  //! Points every 10 m along a ground line that both photos see (30 px from their edges).
  std::vector<Eigen::Vector2d> seenPoints( const OrthophotoPair &pair, const std::vector<Eigen::Vector2d> &line )
  {
    std::vector<Eigen::Vector2d> out;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const int n = std::max( 1, static_cast<int>( ( line[i + 1] - line[i] ).norm() / 10.0 ) );
      for ( int k = 0; k < n; ++k )
      {
        const Eigen::Vector2d xy = line[i] + ( line[i + 1] - line[i] ) * ( static_cast<double>( k ) / n );
        if ( pair.bothSee( Eigen::Vector3d( xy.x(), xy.y(), pair.groundM ), 30.0 ) )
          out.push_back( xy );
      }
    }
    return out;
  }

  struct RevisionFigures
  {
    double confirmed = 0.0, unchangedSeen = 0.0;
    double moved = 0.0, shiftedSeen = 0.0, rmsM = 0.0;
    double notFound = 0.0, notThereSeen = 0.0;
    size_t covered = 0, leftOut = 0;
  };

  //! The map changed on purpose, revised with `options`; the four figures, printed per road.
  RevisionFigures reviseChicago( const std::string &label, const MapRevisionOptions &options )
  {
    const OrthophotoPair pair = chicagoPair();
    const std::vector<std::string> unchanged = { "Michigan Avenue", "Lake Shore Drive", "the street at row 307" };
    std::vector<MapRoad> map;
    for ( const std::string &name : unchanged )
      map.push_back( mapRoad( groundCourse( pair, roadNamed( name ).centre ) ) );
    const std::vector<Eigen::Vector2d> roosevelt = groundCourse( pair, roadNamed( "Roosevelt Road" ).centre );
    map.push_back( mapRoad( groundCourse( pair, roadNamed( "Roosevelt Road" ).centre, 40.0 ) ) );
    map.push_back( mapRoad( groundCourse( pair, { { 30, 372 }, { 170, 428 } } ) ) ); // across the blocks between row 307 and the Eisenhower
    const size_t shifted = unchanged.size(), notThere = shifted + 1;

    const OrientedImage a = pair.photo( 0 ), b = pair.photo( 1 );
    const MapRevisionSummary s = reviseRoads( MatchImage( pair.grey[0] ), MatchImage( pair.grey[1] ), a, b, map, options );

    RevisionFigures f;
    std::printf( "Chicago, map revised, %s (%.1f s):\n", label.c_str(), s.seconds );
    for ( size_t k = 0; k < map.size(); ++k )
    {
      std::printf( "  %s:", k < shifted ? unchanged[k].c_str() : k == shifted ? "Roosevelt Road mapped 40 m north" : "a road mapped where none runs" );
      for ( RevisionStatus status : { RevisionStatus::Confirmed, RevisionStatus::Moved, RevisionStatus::NotFound, RevisionStatus::Occluded } )
        std::printf( " %s %.0f m", revisionStatusName( status ).c_str(), lengthOf( s, k, status ).first );
      std::printf( "\n" );
    }
    for ( size_t k = 0; k < shifted; ++k )
    {
      const auto [c, t] = lengthOf( s, k, RevisionStatus::Confirmed );
      f.confirmed += c;
      f.unchangedSeen += t;
    }
    std::tie( f.moved, f.shiftedSeen ) = lengthOf( s, shifted, RevisionStatus::Moved );
    double sum2 = 0.0;
    int vertices = 0;
    for ( const RevisedPiece &p : s.pieces )
      if ( p.road == shifted && p.status == RevisionStatus::Moved )
        for ( const Eigen::Vector3d &v : p.course )
        {
          sum2 += std::pow( distanceToLines( v.head<2>(), { roosevelt } ), 2 );
          ++vertices;
        }
    f.rmsM = vertices ? std::sqrt( sum2 / vertices ) : 0.0;
    std::tie( f.notFound, f.notThereSeen ) = lengthOf( s, notThere, RevisionStatus::NotFound );

    const std::vector<Eigen::Vector2d> leftOut = seenPoints( pair, groundCourse( pair, roadNamed( "Eisenhower expressway" ).centre ) );
    const double widthM = 2.0 * roadNamed( "Eisenhower expressway" ).halfWidthPx * kGroundPixelM;
    f.leftOut = leftOut.size();
    std::vector<PixelPolyline> newRoads; // on the ground (x, y)
    for ( const NetworkLine &l : s.newRoads )
    {
      newRoads.emplace_back();
      for ( const NetworkVertex &v : l.vertices )
        newRoads.back().push_back( v.point.head<2>() );
    }
    for ( const Eigen::Vector2d &p : leftOut )
      f.covered += distanceToLines( p, newRoads ) <= widthM;
    const auto share = []( double part, double whole ) { return whole > 0 ? part / whole : 0.0; };
    std::printf( "  unchanged confirmed %.2f; shifted moved %.2f (new course %.1f m RMS); not there not found %.2f; left out in NEW %.2f (%zu new lines)\n",
                 share( f.confirmed, f.unchangedSeen ), share( f.moved, f.shiftedSeen ), f.rmsM, share( f.notFound, f.notThereSeen ),
                 share( static_cast<double>( f.covered ), static_cast<double>( f.leftOut ) ), s.newRoads.size() );
    return f;
  }

  void expectAims( const RevisionFigures &f )
  {
    ASSERT_GT( f.unchangedSeen, 2000.0 );
    ASSERT_GT( f.shiftedSeen, 1000.0 );
    ASSERT_GT( f.notThereSeen, 1000.0 );
    EXPECT_GE( f.confirmed, 0.95 * f.unchangedSeen );
    EXPECT_GE( f.moved, 0.90 * f.shiftedSeen );
    EXPECT_LT( f.rmsM, kGroundPixelM );
    EXPECT_GE( f.notFound, 0.90 * f.notThereSeen );
    EXPECT_GE( static_cast<double>( f.covered ), 0.90 * f.leftOut );
  }
} // namespace

// With the defaults, then with MIN_CONTRAST 15 given. Both fail the aims today (disabled until they pass):
// see docs/validation.md.
TEST( RealSatelliteImage, DISABLED_ChicagoMapRevisedWithTheDefaults )
{
  if ( !haveChicagoImage() )
    GTEST_SKIP() << "SP27GTIF.TIF not fetched (scripts/setup-debian.sh)";
  expectAims( reviseChicago( "defaults", MapRevisionOptions() ) );
  MapRevisionOptions given;
  given.network.contrastPerTexture = 0.0;
  given.network.coincident.extraction.object.minContrast = 15.0;
  expectAims( reviseChicago( "contrast 15 given", given ) );
}
