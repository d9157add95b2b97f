/***************************************************************************
  spatialgrid.h - a uniform 2-D bucket grid of item indices
  -------------------------------------------------------------------------
  The simulator registers road segments, objects, ground marks and shadow
  shapes by their bounding boxes and looks up the few near a point.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SPATIALGRID_H
#define GEOSTATION_SIMULATION_SPATIALGRID_H

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  class SpatialGrid
  {
    public:
      SpatialGrid() = default;

      //! A grid over [minXY, maxXY] with square cells of `cellSize` metres.
      SpatialGrid( const Eigen::Vector2d &minXY, const Eigen::Vector2d &maxXY, double cellSize )
        : mMin( minXY ), mCell( cellSize )
      {
        mNx = std::max( 1, static_cast<int>( std::ceil( ( maxXY.x() - minXY.x() ) / cellSize ) ) );
        mNy = std::max( 1, static_cast<int>( std::ceil( ( maxXY.y() - minXY.y() ) / cellSize ) ) );
        mCells.assign( static_cast<size_t>( mNx ) * mNy, {} );
      }

      void insert( int item, const Eigen::Vector2d &boxMin, const Eigen::Vector2d &boxMax )
      {
        const int i0 = cellX( boxMin.x() ), i1 = cellX( boxMax.x() ), j0 = cellY( boxMin.y() ), j1 = cellY( boxMax.y() );
        for ( int j = j0; j <= j1; ++j )
          for ( int i = i0; i <= i1; ++i )
            mCells[static_cast<size_t>( j ) * mNx + i].push_back( item );
      }

      //! The items whose boxes touch the cell containing (x, y).
      const std::vector<int> &at( double x, double y ) const
      {
        static const std::vector<int> kNone;
        if ( mCells.empty() )
          return kNone;
        const double gx = ( x - mMin.x() ) / mCell, gy = ( y - mMin.y() ) / mCell;
        if ( gx < 0 || gy < 0 || gx >= mNx || gy >= mNy )
          return kNone;
        return mCells[static_cast<size_t>( gy ) * mNx + static_cast<int>( gx )];
      }

      double cellSize() const { return mCell; }
      int cellsX() const { return mNx; }
      int cellsY() const { return mNy; }
      const Eigen::Vector2d &minimum() const { return mMin; }
      const std::vector<int> &cell( int i, int j ) const { return mCells[static_cast<size_t>( j ) * mNx + i]; }

    private:
      int cellX( double x ) const { return std::clamp( static_cast<int>( std::floor( ( x - mMin.x() ) / mCell ) ), 0, mNx - 1 ); }
      int cellY( double y ) const { return std::clamp( static_cast<int>( std::floor( ( y - mMin.y() ) / mCell ) ), 0, mNy - 1 ); }

      Eigen::Vector2d mMin = Eigen::Vector2d::Zero();
      double mCell = 1.0;
      int mNx = 0, mNy = 0;
      std::vector<std::vector<int>> mCells;
  };

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SPATIALGRID_H
