/***************************************************************************
  runline.cpp - one station's vertices into the run's traced line
 ***************************************************************************/
#include "tracing/runline.h"

#include <algorithm>
#include <cmath>

#include "tracing/heightcontinuity.h"
#include "tracing/trackgeometry.h"

namespace geostation
{
  namespace
  {
    //! Drops the vertices from `first` on whose height leaves the line through their neighbours'; how many went.
    int dropHeightOutliers( std::vector<TracedVertex> &vertices, size_t first, const HeightContinuityOptions &options )
    {
      std::vector<Eigen::Vector3d> points;
      std::vector<double> sigmaZ;
      for ( const TracedVertex &v : vertices )
      {
        points.push_back( v.point );
        sigmaZ.push_back( std::sqrt( std::max( 0.0, v.covariance( 2, 2 ) ) ) );
      }
      const std::vector<size_t> outliers = heightOutliers( points, sigmaZ, first, options );
      for ( auto it = outliers.rbegin(); it != outliers.rend(); ++it )
        vertices.erase( vertices.begin() + static_cast<std::ptrdiff_t>( *it ) );
      return static_cast<int>( outliers.size() );
    }

    std::vector<const LineVertex3d *> keepLateralCourse( const std::vector<TracedVertex> &line, const std::vector<const LineVertex3d *> &ordered,
        const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &runAlong, const RoadTraceOptions &options, int &dropped )
    {
      struct Accepted
      {
        double arc, offset, sigma;
      };
      const Eigen::Vector3d acrossRun = Eigen::Vector3d( -runAlong.y(), runAlong.x(), 0.0 ).normalized();
      const auto sigmaAcross = [&acrossRun]( const Eigen::Matrix3d &covariance ) { return std::sqrt( std::max( 0.0, acrossRun.dot( covariance * acrossRun ) ) ); };
      std::vector<Accepted> accepted;
      for ( const TracedVertex &v : line )
      {
        const TrackCoordinates c = *trackCoordinates( trajectory, v.point.head<2>() );
        accepted.push_back( { c.arcM, c.leftOffsetM, sigmaAcross( v.covariance ) } );
      }
      // off the line's course: the line's offset over the 10 m before the vertex, the median, with the median
      // of the sigmas; beyond a gap (fewer than 3 there), that of the 3 nearest within 30 m, the allowed step
      // growing by 2 % of the gap (a follower that bridged a shadow onto the parallel edge beside the line)
      const auto offCourse = [&]( const LineVertex3d &v )
      {
        const TrackCoordinates c = *trackCoordinates( trajectory, v.point.head<2>() );
        std::vector<double> offsets, sigmas;
        double gapM = 0.0;
        for ( const Accepted &a : accepted )
          if ( std::abs( a.arc - c.arcM ) <= 10.0 )
          {
            offsets.push_back( a.offset );
            sigmas.push_back( a.sigma );
          }
        if ( offsets.size() < 3 && accepted.size() >= 3 )
        {
          std::vector<const Accepted *> nearest;
          for ( const Accepted &a : accepted )
            nearest.push_back( &a );
          std::partial_sort( nearest.begin(), nearest.begin() + 3, nearest.end(), [&c]( const Accepted *a, const Accepted *b ) { return std::abs( a->arc - c.arcM ) < std::abs( b->arc - c.arcM ); } );
          gapM = std::abs( nearest[0]->arc - c.arcM );
          offsets.clear();
          sigmas.clear();
          if ( std::abs( nearest[2]->arc - c.arcM ) <= 30.0 )
            for ( int k = 0; k < 3; ++k )
            {
              offsets.push_back( nearest[k]->offset );
              sigmas.push_back( nearest[k]->sigma );
            }
        }
        if ( offsets.size() < 3 )
          return false;
        std::nth_element( offsets.begin(), offsets.begin() + offsets.size() / 2, offsets.end() );
        std::nth_element( sigmas.begin(), sigmas.begin() + sigmas.size() / 2, sigmas.end() );
        const double step = std::abs( c.leftOffsetM - offsets[offsets.size() / 2] );
        const double sigma = std::hypot( sigmaAcross( v.covariance ), sigmas[sigmas.size() / 2] );
        return step > std::max( options.maxLateralStepM + 0.02 * gapM, options.heightContinuity.sigmaMultiple * sigma );
      };
      std::vector<const LineVertex3d *> out;
      int inRow = 0;
      for ( size_t i = 0; i < ordered.size(); ++i )
      {
        const LineVertex3d *v = ordered[i];
        if ( offCourse( *v ) )
        {
          ++dropped;
          // the follower left the line: the rest of the station's part goes - unless the next 3 vertices are
          // back on its course (a station's first vertices astray where it was followed back towards its camera)
          if ( ++inRow >= 2 && !( i + 3 < ordered.size() && !offCourse( *ordered[i + 1] ) && !offCourse( *ordered[i + 2] ) && !offCourse( *ordered[i + 3] ) ) )
          {
            dropped += static_cast<int>( ordered.size() - i ) - 1;
            break;
          }
          continue;
        }
        inRow = 0;
        out.push_back( v );
        const TrackCoordinates c = *trackCoordinates( trajectory, v->point.head<2>() );
        accepted.push_back( { c.arcM, c.leftOffsetM, sigmaAcross( v->covariance ) } );
      }
      return out;
    }
  }

  StationPartSummary appendStationPart( std::vector<TracedVertex> &line, const std::vector<LineVertex3d> &vertices, const StationPart &part, const RoadTraceOptions &options )
  {
    const std::vector<TracedVertex> givingWay( line.begin() + static_cast<std::ptrdiff_t>( std::min( part.keep, line.size() ) ), line.end() );
    line.resize( std::min( part.keep, line.size() ) );
    const size_t firstOfStation = line.size();
    const Eigen::Vector3d &runAlong = part.runAlong;
    std::vector<const LineVertex3d *> ordered;
    for ( const LineVertex3d &v : vertices )
    {
      // a road line lies on the road: a vertex far off the surface is a wrong conjugate
      if ( part.surfaceHeight )
        if ( const std::optional<double> surface = part.surfaceHeight( v.point ); surface && std::abs( v.point.z() - *surface ) > options.surfaceToleranceM )
          continue;
      if ( !line.empty() && ( v.point - line.back().point ).head<2>().dot( runAlong.head<2>() ) <= 0 )
        continue;
      ordered.push_back( &v );
    }
    std::stable_sort( ordered.begin(), ordered.end(), [&]( const LineVertex3d *a, const LineVertex3d *b ) { return a->point.head<2>().dot( runAlong.head<2>() ) < b->point.head<2>().dot( runAlong.head<2>() ); } );
    int lateralOutliers = 0;
    if ( part.trajectory && part.trajectory->size() >= 2 && options.maxLateralStepM > 0 )
      ordered = keepLateralCourse( line, ordered, *part.trajectory, runAlong, options, lateralOutliers );
    // the previous station's vertices beyond the handover give way only where this station has vertices of its own
    // (within giveWayM along the run): where this station's line stopped short, they fill its gap
    std::vector<const TracedVertex *> kept;
    for ( const TracedVertex &g : givingWay )
    {
      const double at = g.point.head<2>().dot( runAlong.head<2>().normalized() );
      const bool covered = std::any_of( ordered.begin(), ordered.end(), [&]( const LineVertex3d *v ) {
        return std::abs( v->point.head<2>().dot( runAlong.head<2>().normalized() ) - at ) < options.giveWayM; } );
      if ( !covered )
        kept.push_back( &g );
    }
    for ( const LineVertex3d *v : ordered )
    {
      TracedVertex t;
      t.point = v->point;
      t.sigmaM = v->sigmaM;
      t.covariance = v->covariance;
      t.stationId = part.stationId;
      t.imageIds = { part.referenceImageId, part.partnerImageId };
      t.pixels = { v->pixelInReference, v->pixelInPartner };
      t.residualsPx = { v->residualReferencePx, v->residualPartnerPx };
      for ( const LineVertex3d::OtherObservation &o : v->others )
      {
        t.imageIds.push_back( o.imageId );
        t.pixels.push_back( o.pixelInImage );
        t.residualsPx.push_back( o.residualPx );
      }
      t.rangeM = v->rangeM;
      line.push_back( t );
    }
    if ( !kept.empty() )
    {
      for ( const TracedVertex *g : kept )
        line.push_back( *g );
      std::stable_sort( line.begin() + static_cast<std::ptrdiff_t>( firstOfStation ), line.end(), [&]( const TracedVertex &a, const TracedVertex &b ) {
        return a.point.head<2>().dot( runAlong.head<2>() ) < b.point.head<2>().dot( runAlong.head<2>() ); } );
    }
    const size_t ownVertices = line.size() - firstOfStation - kept.size();
    StationPartSummary out;
    out.firstOfStation = firstOfStation;
    out.heightOutliers = dropHeightOutliers( line, firstOfStation, options.heightContinuity );
    out.lateralOutliers = lateralOutliers;
    out.ownVertices = std::max( 0, static_cast<int>( ownVertices ) - out.heightOutliers );
    return out;
  }

} // namespace geostation
