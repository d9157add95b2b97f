/***************************************************************************
  trajectoryinterpolation.cpp - a vehicle's pose at any time of its trajectory
 ***************************************************************************/
#include "geometry/trajectoryinterpolation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace geostation
{

  TrajectoryInterpolator::TrajectoryInterpolator( std::vector<TrajectoryPose> samples, double maxGapS )
    : mSamples( std::move( samples ) )
    , mMaxGapS( maxGapS )
  {
    if ( !( maxGapS > 0.0 ) )
      throw std::invalid_argument( "the largest gap of a trajectory to interpolate across must be positive" );
    if ( mSamples.size() < 2 )
      throw std::invalid_argument( "a trajectory to interpolate needs at least 2 samples, got " + std::to_string( mSamples.size() ) );
    for ( size_t i = 0; i < mSamples.size(); ++i )
    {
      const TrajectoryPose &s = mSamples[i];
      if ( !std::isfinite( s.timeS ) || !s.position.allFinite() || !s.attitude.allFinite() )
        throw std::invalid_argument( "trajectory sample " + std::to_string( i + 1 ) + " is not finite" );
      if ( i > 0 && !( s.timeS > mSamples[i - 1].timeS ) )
        throw std::invalid_argument( "the trajectory's times must increase: sample " + std::to_string( i + 1 ) + " (" + std::to_string( s.timeS ) + " s) does not come after sample "
                                     + std::to_string( i ) + " (" + std::to_string( mSamples[i - 1].timeS ) + " s)" );
      if ( std::abs( s.attitude.determinant() - 1.0 ) > 1e-6 || !( s.attitude.transpose() * s.attitude ).isIdentity( 1e-6 ) )
        throw std::invalid_argument( "trajectory sample " + std::to_string( i + 1 ) + "'s attitude is not a rotation" );
      Eigen::Quaterniond q( s.attitude );
      q.normalize();
      // one hemisphere along the trajectory, so that neighbours are near each other
      if ( !mRotations.empty() && mRotations.back().dot( q ) < 0.0 )
        q.coeffs() = -q.coeffs();
      mRotations.push_back( q );
    }
  }

  double TrajectoryInterpolator::medianIntervalS() const
  {
    std::vector<double> d;
    for ( size_t i = 1; i < mSamples.size(); ++i )
      d.push_back( mSamples[i].timeS - mSamples[i - 1].timeS );
    std::nth_element( d.begin(), d.begin() + d.size() / 2, d.end() );
    return d[d.size() / 2];
  }

  Eigen::Vector3d TrajectoryInterpolator::velocity( size_t i ) const
  {
    // the samples whose motion belongs to this one: not across a gap
    const auto joined = [this]( size_t a, size_t b ) { return b < mSamples.size() && mSamples[b].timeS - mSamples[a].timeS <= mMaxGapS; };
    size_t from = i, to = i;
    if ( i > 0 && joined( i - 1, i ) )
      from = i - 1;
    if ( joined( i, i + 1 ) )
      to = i + 1;
    // three samples: the derivative of the parabola through them (second order, any spacing)
    if ( from == i && to == i + 1 && joined( i + 1, i + 2 ) )
      to = i + 2;
    else if ( to == i && from == i - 1 && i >= 2 && joined( i - 2, i - 1 ) )
      from = i - 2;
    if ( to - from == 2 )
    {
      const size_t m = from + 1;
      const double t0 = mSamples[from].timeS, t1 = mSamples[m].timeS, t2 = mSamples[to].timeS, t = mSamples[i].timeS;
      // Lagrange basis derivatives at t
      const double l0 = ( 2 * t - t1 - t2 ) / ( ( t0 - t1 ) * ( t0 - t2 ) );
      const double l1 = ( 2 * t - t0 - t2 ) / ( ( t1 - t0 ) * ( t1 - t2 ) );
      const double l2 = ( 2 * t - t0 - t1 ) / ( ( t2 - t0 ) * ( t2 - t1 ) );
      return l0 * mSamples[from].position + l1 * mSamples[m].position + l2 * mSamples[to].position;
    }
    if ( from == to )
      return Eigen::Vector3d::Zero();
    return ( mSamples[to].position - mSamples[from].position ) / ( mSamples[to].timeS - mSamples[from].timeS );
  }

  TrajectoryLookup TrajectoryInterpolator::at( double timeS ) const
  {
    TrajectoryLookup out;
    out.pose.timeS = timeS;
    if ( !std::isfinite( timeS ) )
      throw std::invalid_argument( "the time to interpolate the trajectory at is not finite" );
    if ( timeS < startS() )
    {
      out.status = TrajectoryLookup::Status::BeforeStart;
      return out;
    }
    if ( timeS > endS() )
    {
      out.status = TrajectoryLookup::Status::AfterEnd;
      return out;
    }
    // the samples i, i + 1 around the time
    const auto after = std::upper_bound( mSamples.begin(), mSamples.end(), timeS, []( double t, const TrajectoryPose &s ) { return t < s.timeS; } );
    const size_t i = after == mSamples.end() ? mSamples.size() - 2 : static_cast<size_t>( after - mSamples.begin() ) - 1;
    const TrajectoryPose &p0 = mSamples[i], &p1 = mSamples[i + 1];
    if ( timeS == p0.timeS || timeS == p1.timeS )
    {
      // a sample's own time (an exposure triggered on an epoch of the solution), whatever lies beyond it
      out.pose = timeS == p0.timeS ? p0 : p1;
      return out;
    }
    const double h = p1.timeS - p0.timeS;
    out.gapS = h;
    if ( h > mMaxGapS )
    {
      out.status = TrajectoryLookup::Status::InGap;
      return out;
    }
    const double s = ( timeS - p0.timeS ) / h;
    const double s2 = s * s, s3 = s2 * s;
    // cubic Hermite basis
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    out.pose.position = h00 * p0.position + h10 * h * velocity( i ) + h01 * p1.position + h11 * h * velocity( i + 1 );
    out.pose.attitude = mRotations[i].slerp( s, mRotations[i + 1] ).toRotationMatrix();
    return out;
  }

} // namespace geostation
