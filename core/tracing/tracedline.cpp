/***************************************************************************
  tracedline.cpp
 ***************************************************************************/
#include "tracing/tracedline.h"

#include <algorithm>

namespace geostation
{

  size_t TracedLine::append( const std::vector<TracedVertex> &vertices )
  {
    if ( mVertices.empty() )
    {
      mVertices = vertices;
      return vertices.size();
    }
    // the line's direction at its end, over its last 5 m (plan)
    const Eigen::Vector3d end = mVertices.back().point;
    Eigen::Vector2d along = Eigen::Vector2d::Zero();
    for ( size_t i = mVertices.size() - 1; i-- > 0; )
    {
      along = ( end - mVertices[i].point ).head<2>();
      if ( along.norm() >= 5.0 )
        break;
    }
    if ( along.norm() < 1e-6 && vertices.size() >= 2 )
      along = ( vertices.back().point - vertices.front().point ).head<2>(); // one vertex so far: the new trace's way
    size_t first = 0;
    if ( along.norm() > 1e-6 )
      while ( first < vertices.size() && ( vertices[first].point - end ).head<2>().dot( along ) <= 0.0 )
        ++first;
    mVertices.insert( mVertices.end(), vertices.begin() + first, vertices.end() );
    return vertices.size() - first;
  }

  std::string TracedLine::takeBackLastStation()
  {
    if ( mVertices.empty() )
      return std::string();
    // the station whose part starts last (a station's part may hold a few of the previous station's vertices where
    // it had none of its own, and end before them)
    const std::string station = stationIds().back();
    mVertices.erase( std::remove_if( mVertices.begin(), mVertices.end(), [&]( const TracedVertex &v ) { return v.stationId == station; } ), mVertices.end() );
    return station;
  }

  std::vector<Eigen::Vector3d> TracedLine::points() const
  {
    std::vector<Eigen::Vector3d> out;
    out.reserve( mVertices.size() );
    for ( const TracedVertex &v : mVertices )
      out.push_back( v.point );
    return out;
  }

  double TracedLine::lengthM() const
  {
    double length = 0.0;
    for ( size_t i = 1; i < mVertices.size(); ++i )
      length += ( mVertices[i].point - mVertices[i - 1].point ).norm();
    return length;
  }

  double TracedLine::sigmaMaxM() const
  {
    double sigma = 0.0;
    for ( const TracedVertex &v : mVertices )
      sigma = std::max( sigma, v.sigmaM.maxCoeff() );
    return sigma;
  }

  std::vector<std::string> TracedLine::stationIds() const
  {
    std::vector<std::string> ids;
    for ( const TracedVertex &v : mVertices )
      if ( std::find( ids.begin(), ids.end(), v.stationId ) == ids.end() )
        ids.push_back( v.stationId );
    return ids;
  }

} // namespace geostation
