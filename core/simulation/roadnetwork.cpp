/***************************************************************************
  roadnetwork.cpp - road location and markings for the survey simulator
 ***************************************************************************/
#include "simulation/roadnetwork.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geostation
{

  std::vector<RoadMarkingLine> roadMarkings( const Road &road )
  {
    std::vector<RoadMarkingLine> lines;
    lines.push_back( { "centre", 0.0, 0.15, road.dashedCentre } );
    for ( int lane = 1; lane < road.lanesPerDirection; ++lane )
    {
      lines.push_back( { "separator", lane * road.laneWidthM, 0.15, true } );
      lines.push_back( { "separator", -lane * road.laneWidthM, 0.15, true } );
    }
    lines.push_back( { "edge_line", road.halfWidthM() - 0.3, 0.15, false } );
    lines.push_back( { "edge_line", -( road.halfWidthM() - 0.3 ), 0.15, false } );
    return lines;
  }

  RoadNetwork::RoadNetwork( std::vector<Road> roads )
  {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant( std::numeric_limits<double>::infinity() ), hi = -lo;
    for ( Road &road : roads )
    {
      std::vector<Eigen::Vector2d> dense;
      for ( size_t i = 0; i + 1 < road.centreline.size(); ++i )
      {
        const Eigen::Vector2d a = road.centreline[i], b = road.centreline[i + 1];
        const double len = ( b - a ).norm();
        if ( len < 1e-9 )
          continue;
        const int n = std::max( 1, static_cast<int>( std::ceil( len / 10.0 ) ) );
        for ( int k = 0; k < n; ++k )
          dense.push_back( a + ( b - a ) * ( static_cast<double>( k ) / n ) );
      }
      if ( dense.empty() )
        throw std::invalid_argument( "road " + road.id + " needs at least two distinct vertices" );
      dense.push_back( road.centreline.back() );
      road.centreline = dense;
      std::vector<double> cumulative { 0.0 };
      for ( size_t i = 1; i < dense.size(); ++i )
        cumulative.push_back( cumulative.back() + ( dense[i] - dense[i - 1] ).norm() );
      mCumulative.push_back( cumulative );
      for ( const Eigen::Vector2d &p : dense )
      {
        lo = lo.cwiseMin( p );
        hi = hi.cwiseMax( p );
      }
    }
    mRoads = std::move( roads );
    for ( const Road &road : mRoads )
      mMarkings.push_back( roadMarkings( road ) );
    double reach = 0.0;
    for ( const Road &road : mRoads )
      reach = std::max( reach, road.halfWidthM() + kKerbWidthM + kShoulderWidthM + kBlendReachM );
    if ( mRoads.empty() )
      return;
    // a fine grid reaching the shoulders (every textured sample asks it) and a coarse one reaching the terrain blend
    mGrid = SpatialGrid( lo - Eigen::Vector2d::Constant( reach + 1 ), hi + Eigen::Vector2d::Constant( reach + 1 ), 4.0 );
    mBlendGrid = SpatialGrid( lo - Eigen::Vector2d::Constant( reach + 1 ), hi + Eigen::Vector2d::Constant( reach + 1 ), 16.0 );
    for ( size_t r = 0; r < mRoads.size(); ++r )
    {
      const Road &road = mRoads[r];
      const double roadReach = road.halfWidthM() + kKerbWidthM + kShoulderWidthM + 0.01;
      for ( size_t i = 0; i + 1 < road.centreline.size(); ++i )
      {
        const Eigen::Vector2d a = road.centreline[i], b = road.centreline[i + 1];
        mSegments.push_back( { static_cast<int>( r ), static_cast<int>( i ) } );
        const int item = static_cast<int>( mSegments.size() - 1 );
        mGrid.insert( item, a.cwiseMin( b ) - Eigen::Vector2d::Constant( roadReach ), a.cwiseMax( b ) + Eigen::Vector2d::Constant( roadReach ) );
        mBlendGrid.insert( item, a.cwiseMin( b ) - Eigen::Vector2d::Constant( roadReach + kBlendReachM ),
                           a.cwiseMax( b ) + Eigen::Vector2d::Constant( roadReach + kBlendReachM ) );
      }
    }
  }

  std::optional<RoadLocation> RoadNetwork::nearestOnRoad( int road, double x, double y, bool blendReach ) const
  {
    const Eigen::Vector2d p( x, y );
    double best = std::numeric_limits<double>::infinity();
    RoadLocation location;
    for ( int item : ( blendReach ? mBlendGrid : mGrid ).at( x, y ) )
    {
      const Segment &segment = mSegments[item];
      if ( segment.road != road )
        continue;
      const std::vector<Eigen::Vector2d> &line = mRoads[road].centreline;
      const Eigen::Vector2d a = line[segment.index], b = line[segment.index + 1];
      const Eigen::Vector2d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double u = std::clamp( ( p - a ).dot( ab ) / len2, 0.0, 1.0 );
      const Eigen::Vector2d foot = a + u * ab;
      const double dist = ( p - foot ).norm();
      if ( dist < best )
      {
        best = dist;
        const double len = std::sqrt( len2 );
        location.road = road;
        location.s = mCumulative[road][segment.index] + u * len;
        // signed offset: positive to the left; beyond the ends, the distance along the normal
        location.d = ( ab.x() * ( p.y() - a.y() ) - ab.y() * ( p.x() - a.x() ) ) / len;
        if ( ( u <= 0.0 && segment.index == 0 ) || ( u >= 1.0 && segment.index + 2 == static_cast<int>( line.size() ) ) )
          location.d = std::copysign( dist, location.d == 0.0 ? 1.0 : location.d ); // a round cap past the ends
      }
    }
    if ( location.road < 0 )
      return std::nullopt;
    return location;
  }

  std::optional<RoadLocation> RoadNetwork::locate( double x, double y ) const
  {
    for ( size_t r = 0; r < mRoads.size(); ++r )
    {
      const std::optional<RoadLocation> location = nearestOnRoad( static_cast<int>( r ), x, y );
      if ( location && std::abs( location->d ) <= mRoads[r].halfWidthM() + kKerbWidthM + kShoulderWidthM )
      {
        // a lower-priority road's asphalt beats a higher one's shoulder
        if ( std::abs( location->d ) > mRoads[r].halfWidthM() )
        {
          for ( size_t q = r + 1; q < mRoads.size(); ++q )
          {
            const std::optional<RoadLocation> other = nearestOnRoad( static_cast<int>( q ), x, y );
            if ( other && std::abs( other->d ) <= mRoads[q].halfWidthM() + kKerbWidthM )
              return other;
          }
        }
        return location;
      }
    }
    return std::nullopt;
  }

  std::optional<RoadLocation> RoadNetwork::nearestCentreline( double x, double y, double maxDistanceM ) const
  {
    std::optional<RoadLocation> best;
    for ( size_t r = 0; r < mRoads.size(); ++r )
    {
      const std::optional<RoadLocation> location = nearestOnRoad( static_cast<int>( r ), x, y, true );
      if ( location && std::abs( location->d ) <= maxDistanceM && ( !best || std::abs( location->d ) < std::abs( best->d ) ) )
        best = location;
    }
    return best;
  }

  bool RoadNetwork::onHigherPriorityRoad( int road, double x, double y ) const
  {
    for ( int r = 0; r < road; ++r )
    {
      const std::optional<RoadLocation> location = nearestOnRoad( r, x, y );
      if ( location && std::abs( location->d ) <= mRoads[r].halfWidthM() + kKerbWidthM )
        return true;
    }
    return false;
  }

  Eigen::Vector2d RoadNetwork::pointAt( int road, double s, double d, Eigen::Vector2d *tangent ) const
  {
    const std::vector<double> &cumulative = mCumulative[road];
    const std::vector<Eigen::Vector2d> &line = mRoads[road].centreline;
    s = std::clamp( s, 0.0, cumulative.back() );
    size_t i = std::upper_bound( cumulative.begin(), cumulative.end(), s ) - cumulative.begin();
    i = std::clamp<size_t>( i, 1, line.size() - 1 ) - 1;
    const Eigen::Vector2d a = line[i], b = line[i + 1];
    const double len = cumulative[i + 1] - cumulative[i];
    const Eigen::Vector2d t = ( b - a ) / len;
    if ( tangent )
      *tangent = t;
    return a + t * ( s - cumulative[i] ) + Eigen::Vector2d( -t.y(), t.x() ) * d;
  }

} // namespace geostation
