/***************************************************************************
  stationhandover.cpp - the traced line handed over to the next station
  (stationhandover.h)
 ***************************************************************************/
#include "tracing/stationhandover.h"

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    Handover stopped( TraceStop stop, const std::string &message )
    {
      Handover out;
      out.stop = stop;
      out.message = message;
      return out;
    }

    //! Before the first handover: the neighbour in time (+1, then -1) that lies ahead along the line; 0 if neither.
    int stepAlongLine( const HandoverInput &in, const Eigen::Vector3d &centre )
    {
      const int count = in.track->sequence().size();
      for ( const int s : { 1, -1 } )
        if ( in.station + s >= 0 && in.station + s < count )
          if ( const BlockImage *n = in.track->referenceImageAt( in.station + s ); n &&
               ( n->exterior->projectionCentre - centre ).dot( in.lineDirection ) > 0 )
            return s;
      return 0;
    }

    //! The line's start in a later station's image (dynamiclink.h), or nothing.
    std::optional<DynamicLink> linkTo( const HandoverInput &in, int step, const BlockImage &nextImage, const cv::Mat &nextGrey, const RoadTraceOptions &options )
    {
      const OrientedImage next = in.block->orientedImage( nextImage );
      const Eigen::Vector3d nextCentre = next.exterior().projectionCentre;
      DynamicLinkInput link;
      link.reference = in.reference;
      link.referenceGrey = in.referenceGrey;
      link.next = &next;
      link.nextGrey = &nextGrey;
      link.nextGround = options.groundOfPixel ? options.groundOfPixel : in.track->roadPlaneOf( nextCentre.z(), nextCentre.head<2>() );
      link.vertices = in.vertices;
      link.firstOfStation = in.firstOfStation;
      link.groundLine = in.groundLine;
      link.lineDirection = in.lineDirection;
      link.trajectory = &in.track->trajectory();
      link.step = step;
      link.profile = in.profile;
      link.widthTimesRange = in.widthTimesRange;
      return linkToNextStation( link, options );
    }

    //! Why the line was not found ahead: the follower's own stop where it says more than "it ends".
    Handover notFoundAhead( const HandoverInput &in, const std::string &nextImageId, const std::string &stationId )
    {
      const TraceStop followedStop = in.followed->stop;
      const TraceStop why = followedStop == TraceStop::GapTooLarge || followedStop == TraceStop::DirectionChange ? followedStop : TraceStop::EndOfLine;
      return stopped( why, "the line was not found in " + nextImageId + " ahead of its last vertex (station " + stationId + "): " +
                      ( why == TraceStop::GapTooLarge ? "the gap is too large" : why == TraceStop::DirectionChange ? "it turns too sharply; the operator is needed" : "the line ends or is hidden" ) );
    }
  } // namespace

  Handover handOverToNextStation( const HandoverInput &in, const RoadTraceOptions &options )
  {
    const StationSequence &sequence = in.track->sequence();
    const int count = sequence.size();
    const std::string &id = sequence.at( in.station ).id;
    const Eigen::Vector3d centre = in.reference->exterior().projectionCentre;

    // which way through the run
    const int step = in.step != 0 ? in.step : stepAlongLine( in, centre );
    if ( step == 0 )
    {
      if ( in.station + 1 >= count && in.station - 1 < 0 )
        return stopped( TraceStop::EndOfRun, "the run has no further station" );
      return stopped( TraceStop::StationsOutOfOrder, "neither neighbour of station " + id + " in time order lies ahead along the line: the run's stations are out of order" );
    }
    if ( in.station + step < 0 || in.station + step >= count )
      return stopped( TraceStop::EndOfRun, "the line was traced to the end of the run (station " + id + ")" );

    // the next station: an oriented image in the seed's part, ahead the way the run has gone so far (at the first step, along the line)
    const SequenceStation &nextStation = sequence.at( in.station + step );
    const BlockImage *nextImage = in.track->referenceImageAt( in.station + step );
    if ( !nextImage )
      return stopped( TraceStop::ImageMissing, "station " + nextStation.id + " has no oriented image placed in the rig as " + in.seedImageId + " is" );
    const Eigen::Vector3d runDirection = in.previousCentre ? Eigen::Vector3d( centre - *in.previousCentre ) : in.lineDirection;
    if ( ( nextImage->exterior->projectionCentre - centre ).dot( runDirection ) <= 0 )
      return stopped( TraceStop::StationsOutOfOrder, "station " + nextStation.id + " does not lie ahead of station " + id + " along the line: the run's stations are out of order" );
    const GreyImage next = ( *in.images )( *nextImage );
    if ( !next.ok() )
      return stopped( TraceStop::ImageMissing, next.message );

    // the line there, or at the stations after it that may be passed over
    Handover out;
    out.step = step;
    out.grey = next.grey;
    std::optional<DynamicLink> linked = linkTo( in, step, *nextImage, *next.grey, options );
    int skip = 1;
    for ( int further = 2; !linked && further <= 1 + options.maxStationsPassedOver; ++further )
    {
      const int index = in.station + further * step;
      if ( index < 0 || index >= count )
        break;
      const BlockImage *laterImage = in.track->referenceImageAt( index );
      if ( !laterImage || ( laterImage->exterior->projectionCentre - centre ).dot( runDirection ) <= 0 )
        break;
      const GreyImage later = ( *in.images )( *laterImage );
      if ( !later.ok() )
        break;
      if ( ( linked = linkTo( in, step, *laterImage, *later.grey, options ) ) )
      {
        skip = further;
        out.grey = later.grey;
      }
    }
    if ( !linked )
      return notFoundAhead( in, nextImage->id, id );
    out.station = in.station + skip * step;
    out.passedOver = skip - 1;
    out.link = *linked;
    return out;
  }

} // namespace geostation
