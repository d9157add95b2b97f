/***************************************************************************
  roadtracer.cpp - one click, the whole run traced (thesis §6.5)
 ***************************************************************************/
#include "tracing/roadtracer.h"
#include "tracing/roadtracerun.h"

#include <algorithm>
#include <stdexcept>

namespace geostation
{

  void RoadTraceOptions::check() const
  {
    if ( maxStations < 0 )
      throw std::invalid_argument( "the number of stations must be 0 (the whole run) or more" );
    if ( !( maxRangeM > handoverRangeM ) || !( handoverRangeM > 0 ) )
      throw std::invalid_argument( "the distance limit must be larger than the handover range, and both positive" );
    if ( !( cameraHeightM > 0 ) )
      throw std::invalid_argument( "the camera height above the road must be positive" );
    if ( !( vertexSpacingPx >= 2 ) )
      throw std::invalid_argument( "the vertex spacing must be at least 2 px" );
    if ( minRedundancyToScaleSigma < 0 )
      throw std::invalid_argument( "the redundancy for scaling the sigmas must be 0 (never scaled) or more" );
  }

  std::string RoadTraceSummary::methods() const
  {
    std::vector<std::string> names;
    for ( const TracedStation &s : stations )
    {
      const std::string n = traceMethodName( s.method );
      if ( std::find( names.begin(), names.end(), n ) == names.end() )
        names.push_back( n );
    }
    std::string out;
    for ( const std::string &n : names )
      out += ( out.empty() ? "" : "+" ) + n;
    return out;
  }

  RoadTraceSummary traceRoadLine( const Block &block, const TraceSeed &seed, const RoadTraceOptions &options, const GreyImageSource &images )
  {
    return RoadTraceRun( block, seed, options, images ).run();
  }

} // namespace geostation
