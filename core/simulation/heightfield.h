/***************************************************************************
  heightfield.h - the simulator's terrain: a regular grid of heights
  -------------------------------------------------------------------------
  Heights sit on nodes (the cell centres of the GeoTIFF written by
  writeGeoTiff()) and are interpolated bilinearly between them, exactly as
  Dem (docs/conventions.md §4) interpolates the written file, so the rendered
  terrain, the truth heights and a monoplot against terrain.tif agree.

  Rays are intersected exactly with the bilinear patches (a quadratic in the
  ray parameter per patch), walking a coarse grid of blocks whose maximum
  height lets the walk skip everything the ray passes above.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_HEIGHTFIELD_H
#define GEOSTATION_SIMULATION_HEIGHTFIELD_H

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! Where a ray meets the terrain.
  struct TerrainHit
  {
    double t = 0.0;                                     //!< metres along the (unit) ray
    Eigen::Vector3d point = Eigen::Vector3d::Zero();    //!< block CRS
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  //!< upward unit normal of the bilinear surface
  };

  class HeightField
  {
    public:
      /**
       * A grid of width x height nodes; node (i, j) is at
       * x = originX + i * spacing, y = originY - j * spacing (north up).
       * `heightAt(x, y)` fills every node. Throws std::invalid_argument for
       * fewer than 2 x 2 nodes or a spacing <= 0.
       */
      HeightField( double originX, double originY, double spacing, int width, int height,
                   const std::function<double( double x, double y )> &heightAt );

      int width() const { return mWidth; }
      int height() const { return mHeight; }
      double spacing() const { return mSpacing; }
      double originX() const { return mOriginX; }
      double originY() const { return mOriginY; }
      double minHeight() const { return mMinHeight; }
      double maxHeight() const { return mMaxHeight; }
      double nodeHeight( int i, int j ) const { return mNodes[static_cast<size_t>( j ) * mWidth + i]; }

      //! Whether (x, y) lies between the outermost nodes.
      bool covers( double x, double y ) const;

      //! Bilinear height; nothing outside the grid.
      std::optional<double> heightAt( double x, double y ) const;

      //! Upward unit normal of the bilinear surface at (x, y) (inside the grid).
      Eigen::Vector3d normalAt( double x, double y ) const;

      //! The first intersection with the surface for t in [tMin, tMax]; `direction` is a unit vector.
      std::optional<TerrainHit> intersect( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction,
                                           double tMin = 0.0, double tMax = 1e12 ) const;

      /**
       * Writes the grid as a Float32 GeoTIFF whose cell centres are the nodes,
       * in the CRS `crsWkt` (anything GDAL reads). Throws std::runtime_error.
       */
      void writeGeoTiff( const std::string &path, const std::string &crs ) const;

    private:
      bool intersectPatch( int i, int j, const Eigen::Vector3d &origin, const Eigen::Vector3d &direction,
                           double t0, double t1, double &tHit ) const;
      double blockMax( int bi, int bj ) const { return mBlockMax[static_cast<size_t>( bj ) * mBlocksX + bi]; }
      double superMax( int si, int sj ) const { return mSuperMax[static_cast<size_t>( sj ) * mSupersX + si]; }

      double mOriginX, mOriginY, mSpacing;
      int mWidth, mHeight;
      std::vector<float> mNodes;
      double mMinHeight = 0.0, mMaxHeight = 0.0;
      static constexpr int kBlock = 8; //!< patches per coarse block side
      int mBlocksX = 0, mBlocksY = 0;
      std::vector<float> mBlockMax;
      static constexpr int kSuper = 8; //!< blocks per super-block side
      int mSupersX = 0, mSupersY = 0;
      std::vector<float> mSuperMax;
  };

} // namespace geostation

#endif // GEOSTATION_SIMULATION_HEIGHTFIELD_H
