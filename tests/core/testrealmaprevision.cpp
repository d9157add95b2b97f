/***************************************************************************
  testrealmaprevision.cpp - an old road map held against pairs made from
  real images: a 10 m image of a city and an aerial photograph
  -------------------------------------------------------------------------
  Each image laid on level ground as an orthophoto and photographed by two
  vertical photos of one camera model (orthophotopair.h), with a map made
  from the roads digitised on it and changed on purpose: some roads as they
  are, one mapped some road widths from where it runs, one left out, one
  mapped where none runs.
  - Central Chicago (chicagoimage.h, 10 m): Michigan Avenue, Lake Shore
    Drive and the street at row 307 as they are; Roosevelt Road mapped 40 m
    (4 px) north; the Eisenhower expressway left out; a road mapped
    diagonally across the blocks.
  - aero3.jpg (aero3image.h, laid out at 1 m): the highway as it is; the
    road beside it mapped 25 m east (away from the highway); the cross road
    left out; a road mapped across the forest.
  With the defaults. The aims are those of the painted and simulated
  scenes: unchanged roads confirmed along >= 95 %, the shifted one moved
  along >= 90 % with its new course within 1 m RMS (here: within a ground
  pixel), the road not there not found along >= 90 %, the road left out
  among the new roads along >= 90 %.
 ***************************************************************************/
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "aero3image.h"
#include "chicagoimage.h"
#include "debugdrawing.h"
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
  const TruthRoad &roadNamed( const std::vector<TruthRoad> &roads, const std::string &name )
  {
    return *std::find_if( roads.begin(), roads.end(), [&]( const TruthRoad &r ) { return r.name == name; } );
  }

  //! The road's course on the ground (x, y, no height), moved by `shiftM` (east, north).
  std::vector<Eigen::Vector2d> groundCourse( const OrthophotoPair &pair, const PixelPolyline &orthoLine, const Eigen::Vector2d &shiftM = Eigen::Vector2d::Zero() )
  {
    std::vector<Eigen::Vector2d> out;
    for ( const Eigen::Vector2d &p : orthoLine )
      out.push_back( pair.orthoToGround( p ).head<2>() + shiftM );
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
    double gsdM = 1.0;
  };

  //! A map made from the roads digitised on a real image (orthophoto pixels), changed on purpose.
  struct ChangedMap
  {
    std::string scene;
    OrthophotoPair pair;
    std::vector<TruthRoad> unchanged;
    TruthRoad shifted;
    Eigen::Vector2d shiftM = Eigen::Vector2d::Zero(); //!< east, north
    PixelPolyline notThere;
    TruthRoad leftOut;
  };

  ChangedMap chicagoMap()
  {
    const std::vector<TruthRoad> roads = chicagoMainRoads();
    ChangedMap m;
    m.scene = "Chicago";
    m.pair = chicagoPair();
    for ( const char *name : { "Michigan Avenue", "Lake Shore Drive", "the street at row 307" } )
      m.unchanged.push_back( roadNamed( roads, name ) );
    m.shifted = roadNamed( roads, "Roosevelt Road" );
    m.shiftM = Eigen::Vector2d( 0.0, 40.0 );
    m.notThere = { { 30, 372 }, { 170, 428 } }; // across the blocks between row 307 and the Eisenhower
    m.leftOut = roadNamed( roads, "Eisenhower expressway" );
    return m;
  }

  //! aero3.jpg as an orthophoto of 1 m pixels (the highway 28 m wide), the partner south of it (the roads lie in the photo's lower half).
  ChangedMap aero3Map( const cv::Mat &image )
  {
    const std::vector<TruthRoad> roads = aero3image::aero3MeasuredRoads();
    ChangedMap m;
    m.scene = "aero3";
    m.pair = orthophotoPair( image, 1.0, -0.2 );
    m.unchanged = { roadNamed( roads, "highway" ) };
    m.shifted = roadNamed( roads, "road beside the highway" );
    m.shiftM = Eigen::Vector2d( 25.0, 0.0 );
    m.notThere = { { 20, 420 }, { 90, 445 }, { 165, 470 } }; // across the forest
    m.leftOut = roadNamed( roads, "cross road" );
    return m;
  }

  //! In the first photo: the map (blue), confirmed (green), moved (red: the new course), not found (yellow), new roads (magenta).
  void drawRevision( const std::string &name, const OrthophotoPair &pair, const std::vector<MapRoad> &map, const MapRevisionSummary &s )
  {
    const OrientedImage a = pair.photo( 0 );
    const auto inPhoto = [&]( const auto &points ) {
      PixelPolyline line;
      for ( const auto &p : points )
      {
        const GroundProjection q = a.projectGroundToPixel( Eigen::Vector3d( p.x(), p.y(), pair.groundM ) );
        if ( q.ok() )
          line.push_back( q.pixelInImage );
      }
      return line;
    };
    std::vector<PixelPolyline> mapped, confirmed, moved, notFound, added;
    for ( const MapRoad &road : map )
      mapped.push_back( inPhoto( road.vertices ) );
    for ( const RevisedPiece &p : s.pieces )
      ( p.status == RevisionStatus::Confirmed ? confirmed : p.status == RevisionStatus::Moved ? moved : notFound ).push_back( inPhoto( p.course ) );
    for ( const NetworkLine &l : s.newRoads )
    {
      std::vector<Eigen::Vector3d> points;
      for ( const NetworkVertex &v : l.vertices )
        points.push_back( v.point );
      added.push_back( inPhoto( points ) );
    }
    drawLinesForDebugging( name, pair.grey[0],
                           { { mapped, cv::Scalar( 255, 0, 0 ) }, { confirmed, cv::Scalar( 0, 255, 0 ) }, { moved, cv::Scalar( 0, 0, 255 ) },
                             { notFound, cv::Scalar( 0, 255, 255 ) }, { added, cv::Scalar( 255, 0, 255 ) } } );
  }

  //! The map revised with `options`; the four figures, printed per road.
  RevisionFigures reviseChangedMap( const ChangedMap &m, const std::string &label, const MapRevisionOptions &options )
  {
    const OrthophotoPair &pair = m.pair;
    std::vector<MapRoad> map;
    std::vector<std::string> names;
    for ( const TruthRoad &road : m.unchanged )
    {
      map.push_back( mapRoad( groundCourse( pair, road.centre ) ) );
      names.push_back( road.name );
    }
    const std::vector<Eigen::Vector2d> shiftedTruth = groundCourse( pair, m.shifted.centre );
    map.push_back( mapRoad( groundCourse( pair, m.shifted.centre, m.shiftM ) ) );
    char shiftedName[160];
    std::snprintf( shiftedName, sizeof shiftedName, "%s mapped %.0f m east, %.0f m north", m.shifted.name.c_str(), m.shiftM.x(), m.shiftM.y() );
    names.push_back( shiftedName );
    map.push_back( mapRoad( groundCourse( pair, m.notThere ) ) );
    names.push_back( "a road mapped where none runs" );
    const size_t shifted = m.unchanged.size(), notThere = shifted + 1;

    const OrientedImage a = pair.photo( 0 ), b = pair.photo( 1 );
    const MapRevisionSummary s = reviseRoads( MatchImage( pair.grey[0] ), MatchImage( pair.grey[1] ), a, b, map, options );

    drawRevision( m.scene + "_revision_" + label.substr( 0, label.find( ' ' ) ), pair, map, s );

    RevisionFigures f;
    std::printf( "%s, map revised, %s (%.1f s):\n", m.scene.c_str(), label.c_str(), s.seconds );
    for ( size_t k = 0; k < map.size(); ++k )
    {
      std::printf( "  %s:", names[k].c_str() );
      for ( RevisionStatus status : { RevisionStatus::Confirmed, RevisionStatus::Moved, RevisionStatus::NotFound, RevisionStatus::Occluded } )
        std::printf( " %s %.0f m", revisionStatusName( status ).c_str(), lengthOf( s, k, status ).first );
      std::printf( "\n" );
      if ( std::getenv( "GEOSTATION_EXTRACTION_DEBUG" ) )
        for ( const RevisedPiece &p : s.pieces )
          if ( p.road == k )
            std::printf( "    %.0f-%.0f m %s, evidence %.2f, shift %.1f m\n", p.fromM, p.toM, revisionStatusName( p.status ).c_str(), p.evidence, p.shiftM );
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
          sum2 += std::pow( distanceToLines( v.head<2>(), { shiftedTruth } ), 2 );
          ++vertices;
        }
    f.rmsM = vertices ? std::sqrt( sum2 / vertices ) : 0.0;
    std::tie( f.notFound, f.notThereSeen ) = lengthOf( s, notThere, RevisionStatus::NotFound );

    const std::vector<Eigen::Vector2d> leftOut = seenPoints( pair, groundCourse( pair, m.leftOut.centre ) );
    const double widthM = 2.0 * m.leftOut.halfWidthPx * pair.gsdM;
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
    f.gsdM = pair.gsdM;
    const auto share = []( double part, double whole ) { return whole > 0 ? part / whole : 0.0; };
    std::printf( "  unchanged confirmed %.2f; shifted moved %.2f (new course %.1f m RMS); not there not found %.2f; left out in NEW %.2f (%zu new lines)\n",
                 share( f.confirmed, f.unchangedSeen ), share( f.moved, f.shiftedSeen ), f.rmsM, share( f.notFound, f.notThereSeen ),
                 share( static_cast<double>( f.covered ), static_cast<double>( f.leftOut ) ), s.newRoads.size() );
    return f;
  }

  void expectAims( const RevisionFigures &f )
  {
    // each part of the map seen along some tens of ground pixels at least
    ASSERT_GT( f.unchangedSeen, 50.0 * f.gsdM );
    ASSERT_GT( f.shiftedSeen, 50.0 * f.gsdM );
    ASSERT_GT( f.notThereSeen, 50.0 * f.gsdM );
    ASSERT_GT( f.leftOut, 5u );
    EXPECT_GE( f.confirmed, 0.95 * f.unchangedSeen );
    EXPECT_GE( f.moved, 0.90 * f.shiftedSeen );
    EXPECT_LT( f.rmsM, std::max( 1.0, f.gsdM ) );
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
  const ChangedMap map = chicagoMap();
  expectAims( reviseChangedMap( map, "defaults", MapRevisionOptions() ) );
  MapRevisionOptions given;
  given.network.contrastPerTexture = 0.0;
  given.network.coincident.extraction.object.minContrast = 15.0;
  expectAims( reviseChangedMap( map, "contrast 15 given", given ) );
}

// Fails the aims today (disabled until it passes): the road beside the highway, mapped 25 m east, is moved onto
// the strip of grass between it and the highway (see docs/validation.md).
TEST( RealAerialPhotograph, DISABLED_Aero3MapRevisedWithTheDefaults )
{
  const cv::Mat image = cv::imread( aero3image::sampleImagePath( "aero3.jpg" ), cv::IMREAD_GRAYSCALE );
  ASSERT_FALSE( image.empty() ) << "aero3.jpg (Debian package opencv-doc, installed by scripts/setup-debian.sh)";
  expectAims( reviseChangedMap( aero3Map( image ), "defaults", MapRevisionOptions() ) );
}
