/***************************************************************************
  stationsequence.cpp
 ***************************************************************************/
#include "io/stationsequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>

namespace geostation
{

  StationSequence::StationSequence( const Block &block )
  {
    std::map<std::string, size_t> indexById;
    for ( const Station &s : block.stations )
    {
      indexById[s.id] = mStations.size();
      mStations.push_back( SequenceStation { s.id, s.time, s.trajectory, {}, std::nullopt } );
    }
    for ( const BlockImage &image : block.images )
    {
      auto it = image.stationId.empty() ? indexById.end() : indexById.find( image.stationId );
      if ( it == indexById.end() )
      {
        // an image without (or with an unknown) station is a station of its own
        indexById[image.id] = mStations.size();
        mStations.push_back( SequenceStation { image.id, std::string(), std::string(), { image.id }, std::nullopt } );
      }
      else
        mStations[it->second].imageIds.push_back( image.id );
    }
    mStations.erase( std::remove_if( mStations.begin(), mStations.end(), []( const SequenceStation &s ) { return s.imageIds.empty(); } ), mStations.end() );
    for ( SequenceStation &s : mStations )
    {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int n = 0;
      for ( const std::string &id : s.imageIds )
      {
        const BlockImage &image = block.image( id );
        if ( image.exterior )
        {
          sum += image.exterior->projectionCentre;
          ++n;
        }
      }
      if ( n > 0 )
        s.position = sum / n;
    }
    std::stable_sort( mStations.begin(), mStations.end(), []( const SequenceStation &a, const SequenceStation &b )
    {
      // stations with a time first, in time order; the rest keep the block's order
      if ( a.time.empty() != b.time.empty() )
        return !a.time.empty();
      return a.time < b.time;
    } );
  }

  int StationSequence::indexOf( const std::string &stationId ) const
  {
    for ( int i = 0; i < size(); ++i )
      if ( mStations[i].id == stationId )
        return i;
    return -1;
  }

  std::optional<double> StationSequence::secondsFromIsoTime( const std::string &isoTime )
  {
    int year, month, day, hour = 0, minute = 0;
    double second = 0;
    const int n = std::sscanf( isoTime.c_str(), "%d-%d-%dT%d:%d:%lf", &year, &month, &day, &hour, &minute, &second );
    if ( n < 3 || month < 1 || month > 12 || day < 1 || day > 31 || hour < 0 || hour > 24 || minute < 0 || minute > 59 || second < 0 || second > 61 )
      return std::nullopt;
    std::tm t {};
    t.tm_year = year - 1900;
    t.tm_mon = month - 1;
    t.tm_mday = day;
    t.tm_hour = hour;
    t.tm_min = minute;
    const std::time_t whole = timegm( &t );
    return static_cast<double>( whole ) + second;
  }

  int StationSequence::indexNearestTime( const std::string &isoTime ) const
  {
    const std::optional<double> target = secondsFromIsoTime( isoTime );
    if ( !target )
      return -1;
    int best = -1;
    double bestDt = std::numeric_limits<double>::infinity();
    for ( int i = 0; i < size(); ++i )
    {
      const std::optional<double> t = secondsFromIsoTime( mStations[i].time );
      if ( t && std::abs( *t - *target ) < bestDt )
      {
        bestDt = std::abs( *t - *target );
        best = i;
      }
    }
    return best;
  }

  int StationSequence::indexOfIdOrTime( const std::string &idOrTime ) const
  {
    const int index = indexOf( idOrTime );
    return index >= 0 ? index : indexNearestTime( idOrTime );
  }

  int StationSequence::indexNearest( const Eigen::Vector2d &pointInWorld ) const
  {
    int best = -1;
    double bestD2 = std::numeric_limits<double>::infinity();
    for ( int i = 0; i < size(); ++i )
    {
      if ( !mStations[i].position )
        continue;
      const double d2 = ( mStations[i].position->head<2>() - pointInWorld ).squaredNorm();
      if ( d2 < bestD2 )
      {
        bestD2 = d2;
        best = i;
      }
    }
    return best;
  }

  int StationSequence::stepped( int index, int step ) const
  {
    if ( mStations.empty() )
      return -1;
    return std::clamp( index + step, 0, size() - 1 );
  }

} // namespace geostation
