/***************************************************************************
  linetrace.cpp - names and directions shared by the road-line followers
 ***************************************************************************/
#include "tracing/linetrace.h"
#include "geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geostation
{
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

  std::vector<TraceMethod> autoMethodOrder( const LineProfile &profile )
  {
    if ( profile.kind == LineKind::BrightStripe )
      return { TraceMethod::Polynomial, TraceMethod::Directional };
    return { TraceMethod::LeastSquares, TraceMethod::Polynomial, TraceMethod::Directional };
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

  void joinBackward( const FollowResult &backward, FollowResult &forward )
  {
    if ( backward.points.size() < 2 )
      return;
    std::vector<Eigen::Vector2d> both( backward.points.rbegin(), backward.points.rend() );
    std::vector<double> bothSigma( backward.sigmaPx.rbegin(), backward.sigmaPx.rend() );
    const size_t skip = !forward.points.empty() && ( forward.points.front() - both.back() ).norm() < 3.0 ? 1 : 0;
    both.insert( both.end(), forward.points.begin() + std::min( skip, forward.points.size() ), forward.points.end() );
    bothSigma.insert( bothSigma.end(), forward.sigmaPx.begin() + std::min( skip, forward.sigmaPx.size() ), forward.sigmaPx.end() );
    // bridged flags: reversed, the flag of the segment ending at point i + 1 is the original's of point n - 1 - i
    const size_t n = backward.points.size();
    std::vector<bool> bothBridged( n, false );
    for ( size_t i = 0; i + 1 < n; ++i )
      bothBridged[i + 1] = n - 1 - i < backward.bridged.size() && backward.bridged[n - 1 - i];
    // (where the two do not meet at the start, the start lay in a gap: the segment joining them is bridged)
    for ( size_t i = std::min( skip, forward.points.size() ); i < forward.points.size(); ++i )
      bothBridged.push_back( i > 0 ? i < forward.bridged.size() && forward.bridged[i] : skip == 0 );
    forward.points = both;
    forward.sigmaPx = bothSigma;
    forward.bridged = bothBridged;
  }

} // namespace geostation
