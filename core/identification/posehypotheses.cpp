/***************************************************************************
  posehypotheses.cpp - camera poses from triangles of control and candidates
 ***************************************************************************/
#include "identification/posehypotheses.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

namespace geostation
{

  ControlPairs matchOneToOne( std::vector<std::tuple<double, int, int>> proposals )
  {
    std::sort( proposals.begin(), proposals.end() );
    std::set<int> usedControl, usedCandidate;
    ControlPairs pairs;
    for ( const auto &[d, j, i] : proposals )
      if ( !usedControl.count( j ) && !usedCandidate.count( i ) )
      {
        usedControl.insert( j );
        usedCandidate.insert( i );
        pairs.emplace_back( j, i );
      }
    std::sort( pairs.begin(), pairs.end() );
    return pairs;
  }

  //! Candidates in ideal normalised coordinates on a grid, for nearest-neighbour queries within one cell.
  class PoseHypotheses::Grid
  {
    public:
      Grid( const std::vector<Eigen::Vector2d> &ideal, double cell ) : mIdeal( ideal ), mCell( cell )
      {
        mLo = Eigen::Vector2d( 1e300, 1e300 );
        Eigen::Vector2d hi( -1e300, -1e300 );
        for ( const Eigen::Vector2d &u : ideal )
        {
          mLo = mLo.cwiseMin( u );
          hi = hi.cwiseMax( u );
        }
        mCols = static_cast<int>( ( hi.x() - mLo.x() ) / cell ) + 1;
        mRows = static_cast<int>( ( hi.y() - mLo.y() ) / cell ) + 1;
        mCells.assign( static_cast<size_t>( mCols ) * mRows, {} );
        for ( int i = 0; i < static_cast<int>( ideal.size() ); ++i )
          mCells[static_cast<size_t>( cellOf( ideal[i].y(), mLo.y() ) ) * mCols + cellOf( ideal[i].x(), mLo.x() )].push_back( i );
      }

      //! The nearest candidate within one cell size, or -1.
      int nearest( const Eigen::Vector2d &u, double &distance ) const
      {
        const int c0 = cellOf( u.x(), mLo.x() ), r0 = cellOf( u.y(), mLo.y() );
        int best = -1;
        double bestD2 = mCell * mCell;
        for ( int r = std::max( 0, r0 - 1 ); r <= std::min( mRows - 1, r0 + 1 ); ++r )
          for ( int c = std::max( 0, c0 - 1 ); c <= std::min( mCols - 1, c0 + 1 ); ++c )
            for ( int i : mCells[static_cast<size_t>( r ) * mCols + c] )
            {
              const double d2 = ( mIdeal[i] - u ).squaredNorm();
              if ( d2 <= bestD2 )
              {
                bestD2 = d2;
                best = i;
              }
            }
        distance = std::sqrt( bestD2 );
        return best;
      }

    private:
      int cellOf( double v, double lo ) const
      {
        const double k = std::floor( ( v - lo ) / mCell );
        return k < -1e6 ? -1000000 : ( k > 1e6 ? 1000000 : static_cast<int>( k ) );
      }

      const std::vector<Eigen::Vector2d> &mIdeal;
      double mCell;
      Eigen::Vector2d mLo;
      int mCols = 0, mRows = 0;
      std::vector<std::vector<int>> mCells;
  };

  namespace
  {
    //! The `count` members of `among` nearest to `k` (not k itself).
    template <typename Distance>
    std::vector<int> nearestOf( int k, const std::vector<int> &among, int count, Distance distance )
    {
      std::vector<std::pair<double, int>> d;
      for ( int m : among )
        if ( m != k )
          d.emplace_back( distance( k, m ), m );
      const int n = std::min<int>( count, static_cast<int>( d.size() ) );
      std::partial_sort( d.begin(), d.begin() + n, d.end() );
      std::vector<int> out;
      for ( int q = 0; q < n; ++q )
        out.push_back( d[q].second );
      return out;
    }
  } // namespace

  PoseHypotheses::PoseHypotheses( const std::vector<Eigen::Vector3d> &local, const std::vector<Eigen::Vector2d> &ideal, const std::vector<double> &worth,
                                  const std::vector<int> &groundControl, const std::vector<int> &imageCandidates, const std::vector<std::vector<int>> &allowed,
                                  const PoseHypothesisOptions &options )
    : mLocal( local ), mIdeal( ideal ), mWorth( worth ), mAllowed( allowed ), mOptions( options ), mGrid( std::make_unique<Grid>( ideal, options.tolerance ) )
  {
    std::set<std::array<int, 3>> triangles;
    for ( int j : groundControl )
    {
      const std::vector<int> near = nearestOf( j, groundControl, options.neighboursOnGround, [&]( int a, int b ) { return ( local[a] - local[b] ).norm(); } );
      for ( size_t a = 0; a < near.size(); ++a )
        for ( size_t b = a + 1; b < near.size(); ++b )
          triangles.insert( { j, near[a], near[b] } );
    }
    mTriangles.assign( triangles.begin(), triangles.end() );
    mImageNeighbours.resize( ideal.size() );
    for ( int k : imageCandidates )
      mImageNeighbours[k] = nearestOf( k, imageCandidates, options.neighboursInImage, [&]( int a, int b ) { return ( ideal[a] - ideal[b] ).norm(); } );
  }

  PoseHypotheses::~PoseHypotheses() = default;

  ControlPairs PoseHypotheses::pairsOf( const ThreePointPose &pose ) const
  {
    std::vector<std::tuple<double, int, int>> proposals;
    for ( int j = 0; j < static_cast<int>( mLocal.size() ); ++j )
    {
      const Eigen::Vector3d p = pose.cameraFromWorld * ( mLocal[j] - pose.centre );
      if ( !( p.z() < 0.0 ) )
        continue;
      double d = 0.0;
      const int i = mGrid->nearest( Eigen::Vector2d( -p.x() / p.z(), -p.y() / p.z() ), d );
      if ( i >= 0 )
        proposals.emplace_back( d, j, i );
    }
    return matchOneToOne( std::move( proposals ) );
  }

  void PoseHypotheses::addFrom( int i )
  {
    auto worse = []( const PoseHypothesis &a, const PoseHypothesis &b ) { return a.score > b.score; };
    const bool guided = !mAllowed.empty();
    for ( const std::array<int, 3> &t : mTriangles )
    {
      if ( guided && !std::binary_search( mAllowed[t[0]].begin(), mAllowed[t[0]].end(), i ) )
        continue;
      const Eigen::Vector3d &A = mLocal[t[0]], &B = mLocal[t[1]], &C = mLocal[t[2]];
      const Eigen::Vector3d normal = ( B - A ).cross( C - A );
      const double sides[3] = { ( B - A ).norm(), ( C - A ).norm(), ( C - B ).norm() };
      if ( normal.norm() < 1e-3 * std::max( sides[0], sides[1] ) * std::max( sides[0], sides[1] ) )
        continue; // collinear on the ground
      const bool flat = std::abs( normal.z() ) >= 0.5 * normal.norm();
      const std::vector<int> &seconds = guided ? mAllowed[t[1]] : mImageNeighbours[i];
      const std::vector<int> &thirds = guided ? mAllowed[t[2]] : mImageNeighbours[i];
      for ( int p : seconds )
        for ( int q : thirds )
        {
          if ( p == q || p == i || q == i )
            continue;
          const Eigen::Vector2d u = mIdeal[p] - mIdeal[i], v = mIdeal[q] - mIdeal[i];
          const double cross = u.x() * v.y() - u.y() * v.x();
          if ( flat && ( cross > 0.0 ) != ( normal.z() > 0.0 ) )
            continue; // mirrored
          const double lengths[3] = { u.norm(), v.norm(), ( mIdeal[q] - mIdeal[p] ).norm() };
          double lo = 1e300, hi = 0.0;
          for ( int s = 0; s < 3; ++s )
          {
            lo = std::min( lo, lengths[s] / sides[s] );
            hi = std::max( hi, lengths[s] / sides[s] );
          }
          if ( !( lo > 0.0 ) || hi > mOptions.maxForeshortening * lo || std::min( { lengths[0], lengths[1], lengths[2] } ) < mOptions.minSideIdeal )
            continue;
          ++mTriangleCount;
          for ( const ThreePointPose &pose : threePointPoses( { A, B, C }, { mIdeal[i], mIdeal[p], mIdeal[q] } ) )
          {
            ++mPoseCount;
            const ControlPairs pairs = pairsOf( pose );
            if ( pairs.size() < 4 )
              continue;
            double score = 0.0;
            for ( const auto &pair : pairs )
              score += mWorth[pair.second];
            if ( mHeap.size() >= mOptions.kept && score <= mHeap.front().score )
              continue;
            mHeap.push_back( { score, pose } );
            std::push_heap( mHeap.begin(), mHeap.end(), worse );
            if ( mHeap.size() > mOptions.kept )
            {
              std::pop_heap( mHeap.begin(), mHeap.end(), worse );
              mHeap.pop_back();
            }
          }
        }
    }
  }

  std::vector<PoseHypothesis> PoseHypotheses::best() const
  {
    std::vector<PoseHypothesis> sorted = mHeap;
    std::sort( sorted.begin(), sorted.end(), []( const PoseHypothesis &a, const PoseHypothesis &b ) { return a.score > b.score; } );
    return sorted;
  }

} // namespace geostation
