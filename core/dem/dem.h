/***************************************************************************
  dem.h - a digital elevation model read through GDAL (CONVENTIONS §4)
  -------------------------------------------------------------------------
  Heights sit at the cell centres of the raster's geotransform and are
  interpolated bilinearly in the DEM's own CRS, so a point on the surface is
  found exactly whatever the CRS. The raster is read in tiles on demand and
  kept in a small least-recently-used cache, so a 20 000 x 20 000 DEM never
  has to be in memory. Nodata holes are filled as the monoplotter paper does:
  each empty cell takes the mean of its present neighbours in X and Y,
  repeated inward, within a halo around each tile; filled cells are counted.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_DEM_H
#define GEOSTATION_DEM_DEM_H

#include <array>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  struct DemOptions
  {
    int tileSize = 256;       //!< cells per tile side
    int holeFillHalo = 16;    //!< holes up to about twice this many cells across are filled
    size_t cacheTiles = 64;   //!< tiles kept in memory
  };

  class Dem
  {
    public:
      /**
       * Opens a single-band raster. Throws std::runtime_error if it cannot be
       * read, has no CRS or no geotransform.
       */
      explicit Dem( const std::string &path, const DemOptions &options = DemOptions() );
      ~Dem();
      Dem( const Dem & ) = delete;
      Dem &operator=( const Dem & ) = delete;

      const std::string &crsWkt() const { return mCrsWkt; }
      bool isGeographic() const { return mGeographic; }
      int width() const { return mWidth; }
      int height() const { return mHeight; }
      //! The six GDAL geotransform coefficients.
      const std::array<double, 6> &geoTransform() const { return mGeoTransform; }

      /**
       * Bilinear height at (x, y) in the DEM's CRS; nothing outside the area
       * between the outermost cell centres or on a hole too large to fill.
       */
      std::optional<double> heightAt( double x, double y ) const;

      //! Height, coverage and slope bound at one point, for ray marching.
      struct Sample
      {
        std::optional<double> height; //!< as heightAt()
        bool covers = false;          //!< as covers()
        double slopeBound = 0.0;      //!< as slopeBoundAt(), 0 outside
      };

      //! heightAt(), covers() and slopeBoundAt() in one pass.
      Sample sample( double x, double y ) const;

      //! Whether (x, y) lies in the area between the outermost cell centres.
      bool covers( double x, double y ) const;

      int tileSize() const { return mOptions.tileSize; }

      /**
       * An upper bound of the surface slope (height units per horizontal
       * metre) over the tile containing (x, y) and its neighbours; nothing
       * outside the DEM.
       */
      std::optional<double> slopeBoundAt( double x, double y ) const;

      //! Horizontal metres per CRS unit near (x, y) along x and y (1 for projected CRSs).
      Eigen::Vector2d metresPerUnit( double x, double y ) const;

      //! Cells filled so far (in tiles read so far).
      long filledCellCount() const { return mFilledCells; }

    private:
      struct Tile
      {
        std::vector<float> values; //!< tileSize^2, NaN where still empty
        double slopeBound = 0.0;
        double minHeight = 0.0, maxHeight = 0.0;
      };
      const Tile *tile( int tileX, int tileY ) const;
      std::optional<double> heightAtPixel( double px, double py ) const;
      double slopeBoundAtPixel( double px, double py ) const;
      std::optional<double> cell( int col, int row ) const;

      DemOptions mOptions;
      void *mDataset = nullptr;
      std::string mCrsWkt;
      bool mGeographic = false;
      int mWidth = 0, mHeight = 0;
      std::array<double, 6> mGeoTransform {};
      std::array<double, 6> mInverse {};
      std::optional<double> mNoData;
      mutable std::map<std::pair<int, int>, std::pair<std::unique_ptr<Tile>, std::list<std::pair<int, int>>::iterator>> mTiles;
      mutable std::list<std::pair<int, int>> mRecent; //!< most recent first
      mutable std::pair<int, int> mLastKey { -1, -1 };  //!< the tile used last, without a map lookup
      mutable const Tile *mLastTile = nullptr;
      mutable std::pair<int, int> mLastSlopeKey { -1, -1 };
      mutable double mLastSlope = 0.0;
      mutable long mFilledCells = 0;
  };

} // namespace geostation

#endif // GEOSTATION_DEM_DEM_H
