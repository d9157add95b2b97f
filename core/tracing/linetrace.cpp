/***************************************************************************
  linetrace.cpp - names and directions shared by the road-line followers
 ***************************************************************************/
#include "tracing/linetrace.h"

#include <cmath>
#include <stdexcept>

namespace geostation
{
  namespace
  {
    constexpr double kPi = 3.14159265358979323846;
  }

  std::string lineKindName( LineKind kind )
  {
    switch ( kind )
    {
      case LineKind::BrightStripe:
        return "bright_stripe";
      case LineKind::DarkStripe:
        return "dark_stripe";
      case LineKind::Edge:
        return "edge";
    }
    return "edge";
  }

  std::string traceMethodName( TraceMethod method )
  {
    switch ( method )
    {
      case TraceMethod::Auto:
        return "auto";
      case TraceMethod::Directional:
        return "directional";
      case TraceMethod::LeastSquares:
        return "least_squares";
      case TraceMethod::Polynomial:
        return "polynomial";
    }
    return "auto";
  }

  TraceMethod traceMethodFromName( const std::string &name )
  {
    for ( const TraceMethod m : { TraceMethod::Auto, TraceMethod::Directional, TraceMethod::LeastSquares, TraceMethod::Polynomial } )
      if ( traceMethodName( m ) == name )
        return m;
    throw std::invalid_argument( "unknown tracing method \"" + name + "\" (auto, directional, least_squares, polynomial)" );
  }

  std::string traceStopName( TraceStop stop )
  {
    switch ( stop )
    {
      case TraceStop::EndOfLine:
        return "end_of_line";
      case TraceStop::GapTooLarge:
        return "gap_too_large";
      case TraceStop::DirectionChange:
        return "direction_change";
      case TraceStop::LeftImage:
        return "left_images";
      case TraceStop::DistanceLimit:
        return "distance_limit";
      case TraceStop::EndOfRun:
        return "end_of_run";
      case TraceStop::MaxStations:
        return "max_stations";
      case TraceStop::Cancelled:
        return "cancelled";
      case TraceStop::NoEdge:
        return "no_edge";
      case TraceStop::NoStereoPartner:
        return "no_stereo_partner";
      case TraceStop::ImageMissing:
        return "image_missing";
      case TraceStop::StationsOutOfOrder:
        return "stations_out_of_order";
    }
    return "end_of_line";
  }

  Eigen::Vector2d directionFromDegrees( double degrees )
  {
    const double a = degrees * kPi / 180.0;
    return Eigen::Vector2d( std::sin( a ), -std::cos( a ) );
  }

  double degreesFromDirection( const Eigen::Vector2d &direction )
  {
    return std::atan2( direction.x(), -direction.y() ) * 180.0 / kPi;
  }

} // namespace geostation
