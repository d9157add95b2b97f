/***************************************************************************
  leastsquaresfollower.cpp - least-squares line following (§6.3.2)
 ***************************************************************************/
#include "tracing/leastsquaresfollower.h"
#include "geometry/rotation.h"

#include <cmath>
#include <deque>

#include <Eigen/Dense>

namespace geostation
{
  namespace
  {
    //! Pixel space seen as (across, step): rows are stepped for a steep line, columns otherwise.
    struct Frame
    {
      bool stepRows = true;
      int sign = -1; //!< step direction along the stepped axis

      Eigen::Vector2d pixel( double across, double step ) const { return stepRows ? Eigen::Vector2d( across, step ) : Eigen::Vector2d( step, across ); }
      double across( const Eigen::Vector2d &p ) const { return stepRows ? p.x() : p.y(); }
      double step( const Eigen::Vector2d &p ) const { return stepRows ? p.y() : p.x(); }
      //! Across-shift per step of a direction.
      double slope( const Eigen::Vector2d &d ) const { return ( stepRows ? d.x() : d.y() ) / std::abs( stepRows ? d.y() : d.x() ); }

      static Frame of( const Eigen::Vector2d &d )
      {
        Frame f;
        f.stepRows = std::abs( d.y() ) >= std::abs( d.x() );
        f.sign = ( f.stepRows ? d.y() : d.x() ) >= 0 ? 1 : -1;
        return f;
      }
    };

    //! A window of two lines (step, step + sign) across `centre` +- half; false if it leaves the image.
    bool window( const cv::Mat &grey, const Frame &f, double centre, double stepCentre, int half, Eigen::VectorXd &values, Eigen::VectorXd *gradient )
    {
      values.resize( 2 * ( 2 * half + 1 ) );
      if ( gradient )
        gradient->resize( values.size() );
      int i = 0;
      for ( int line = 0; line < 2; ++line )
        for ( int k = -half; k <= half; ++k, ++i )
        {
          const double s = stepCentre + line * f.sign;
          const std::optional<double> g = sampleGrey( grey, f.pixel( centre + k, s ) );
          if ( !g )
            return false;
          values[i] = *g;
          if ( gradient )
          {
            const std::optional<double> a = sampleGrey( grey, f.pixel( centre + k + 1, s ) ), b = sampleGrey( grey, f.pixel( centre + k - 1, s ) );
            if ( !a || !b )
              return false;
            ( *gradient )[i] = 0.5 * ( *a - *b );
          }
        }
      return true;
    }

    double correlation( const Eigen::VectorXd &a, const Eigen::VectorXd &b )
    {
      const Eigen::VectorXd x = a.array() - a.mean(), y = b.array() - b.mean();
      const double d = std::sqrt( x.squaredNorm() * y.squaredNorm() );
      return d > 0 ? x.dot( y ) / d : 0.0;
    }
  }

  FollowResult followLeastSquares( const cv::Mat &grey, const FollowRequest &request, const LeastSquaresFollowOptions &options )
  {
    FollowResult out;
    out.profile = request.profile;
    const int half = request.profile.kind == LineKind::Edge
                     ? options.windowHalfWidthPx
                     : std::max( options.windowHalfWidthPx, static_cast<int>( std::ceil( 1.25 * request.profile.widthPx + 3 ) ) );
    Eigen::Vector2d direction = request.direction.normalized();
    Frame frame = Frame::of( direction );
    // the position sits on a pixel-centre line of the stepped axis
    double stepCentre = std::floor( frame.step( request.start ) ) + 0.5;
    double across = frame.across( request.start ) + frame.slope( direction ) * ( stepCentre - frame.step( request.start ) ) * frame.sign;
    Eigen::VectorXd target;
    if ( !window( grey, frame, across, stepCentre, half, target, nullptr ) )
    {
      out.stop = TraceStop::LeftImage;
      return out;
    }
    out.points.push_back( frame.pixel( across, stepCentre + 0.5 * frame.sign ) );
    out.sigmaPx.push_back( 0.3 );
    std::deque<Eigen::Vector2d> recent { out.points.back() };
    Eigen::Vector2d countPoint = out.points.back(), countDirection = direction;
    out.stop = TraceStop::EndOfLine;

    for ( int step = 0; step < request.maxSteps; ++step )
    {
      const double slope = frame.slope( direction );
      if ( std::abs( slope ) > 1.05 )
      {
        // the line now runs closer to the other axis: step that one, with a fresh target
        frame = Frame::of( direction );
        const Eigen::Vector2d p = out.points.back();
        stepCentre = std::floor( frame.step( p ) ) + 0.5;
        across = frame.across( p );
        if ( !window( grey, frame, across, stepCentre, half, target, nullptr ) )
        {
          out.stop = TraceStop::LeftImage;
          break;
        }
        continue;
      }
      const double nextStep = stepCentre + frame.sign;
      const double predicted = across + frame.slope( direction );
      double a = predicted, gain = 1.0, offset = 0.0, sigma = 0.0;
      Eigen::VectorXd values, gradient;
      bool inside = true, converged = false;
      for ( int it = 0; it < options.maxIterations; ++it )
      {
        if ( !window( grey, frame, a, nextStep, half, values, &gradient ) )
        {
          inside = false;
          break;
        }
        Eigen::MatrixXd design( values.size(), 3 );
        design.col( 0 ) = gain * gradient;
        design.col( 1 ).setOnes();
        design.col( 2 ) = values;
        const Eigen::VectorXd w = target - ( ( gain * values ).array() + offset ).matrix();
        const Eigen::Matrix3d normal = design.transpose() * design;
        if ( std::abs( normal.determinant() ) < 1e-9 )
          break;
        const Eigen::Vector3d dx = normal.ldlt().solve( design.transpose() * w );
        a += dx[0];
        offset += dx[1];
        gain += dx[2];
        const double redundancy = std::max( 1.0, static_cast<double>( values.size() - 3 ) );
        const double s0 = std::sqrt( ( w - design * dx ).squaredNorm() / redundancy );
        sigma = s0 * std::sqrt( std::max( 0.0, normal.inverse()( 0, 0 ) ) );
        if ( std::abs( dx[0] ) < options.convergencePx )
        {
          converged = true;
          break;
        }
        if ( std::abs( a - predicted ) > options.maxShiftPx )
          break;
      }
      if ( !inside )
      {
        out.stop = TraceStop::LeftImage;
        break;
      }
      if ( !converged || std::abs( a - predicted ) > options.maxShiftPx || gain < 0.5 || gain > 2.0 || !window( grey, frame, a, nextStep, half, values, nullptr ) ||
           correlation( target, values ) < options.minCorrelation )
        break; // the line is lost here
      const Eigen::Vector2d point = frame.pixel( a, nextStep + 0.5 * frame.sign );
      if ( request.withinLimit && !request.withinLimit( point ) )
      {
        out.stop = TraceStop::DistanceLimit;
        break;
      }
      out.points.push_back( point );
      out.sigmaPx.push_back( std::max( 0.05, sigma ) );
      ++out.pixelsFollowed;
      target = ( 1.0 - options.templateUpdate ) * target + options.templateUpdate * ( gain * values.array() + offset ).matrix();
      across = a;
      stepCentre = nextStep;
      // the direction from the last few rows; checked against the limit every update distance
      recent.push_back( point );
      if ( recent.size() > 10 )
        recent.pop_front();
      if ( recent.size() >= 5 )
        direction = ( recent.back() - recent.front() ).normalized();
      if ( ( point - countPoint ).norm() >= options.follow.directionUpdatePx )
      {
        const Eigen::Vector2d updated = ( point - countPoint ).normalized();
        if ( std::acos( std::clamp( updated.dot( countDirection ), -1.0, 1.0 ) ) * 180.0 / kPi > options.follow.maxDirectionChangeDeg )
        {
          out.stop = TraceStop::DirectionChange;
          break;
        }
        countDirection = updated;
        countPoint = point;
      }
    }
    out.direction = direction;
    return out;
  }

} // namespace geostation
