/***************************************************************************
  dem.h - a digital elevation model read through GDAL (docs/conventions.md §4)
  -------------------------------------------------------------------------
  Heights sit at the cell centres of the raster's geotransform and are
  interpolated bilinearly in the DEM's own CRS, so a point on the surface is
  found exactly whatever the CRS. The raster is read in tiles on demand and
  kept in a small least-recently-used cache, so a 20 000 x 20 000 DEM never
  has to be in memory. Nodata holes are filled as Stokes (1988) does:
  each empty cell takes the mean of its present neighbours in X and Y,
  repeated inward, within a halo around each tile (as if the whole raster
  were filled); filled cells are counted. Larger holes can be bridged
  (DemOptions::bridgeHolesUpToCells): linear interpolation across the hole
  along rows and columns, each bridged cell with a height sigma
  (bridgeSigmaAt()). Tiles also keep block maxima for
  the ray / DEM traversal. Not for concurrent use.
 ***************************************************************************/
#ifndef GEOSTATION_DEM_DEM_H
#define GEOSTATION_DEM_DEM_H

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  struct DemOptions
  {
    int tileSize = 256;       //!< cells per tile side, a multiple of Dem::kBlockSize
    int holeFillHalo = 16;    //!< holes up to about twice this many cells across are filled
    size_t cacheTiles = 64;   //!< tiles kept in memory
    /**
     * Holes too large to fill but at most this many cells across (along a
     * row or a column) are bridged: each of the hole's cells (the fill's
     * rings included) takes the linear interpolation between the data at
     * the hole's rims along its row and its column (their mean where both
     * reach across). 0: not bridged.
     */
    int bridgeHolesUpToCells = 0;
    /**
     * A bridged height's sigma: what the terrain's curvature just outside
     * the rims makes of a straight line across the hole (kappa d1 d2 / 2,
     * d1 and d2 the distances to the rims), at least this many metres per
     * metre from the nearer rim (an unseen change of slope); with both a
     * row and a column across, also half their difference.
     */
    double bridgeSigmaPerMetre = 0.05;
  };

  class Dem
  {
    public:
      /**
       * Opens a single-band raster. Throws std::runtime_error if it cannot be
       * read, has no CRS or no geotransform. Cells at the nodata value, not
       * finite, or beyond +-1e6 (undeclared sentinels such as -3.4e38) are
       * holes. Tiles are read when first
       * needed: every method that reads heights (heightAt(), tileView(), ray
       * intersection) throws std::runtime_error naming the file when a tile
       * of it cannot be read (a corrupt block).
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

      int tileSize() const { return mOptions.tileSize; }
      //! Holes up to about twice this many cells across are filled from their neighbours.
      int holeFillHalo() const { return mOptions.holeFillHalo; }

      //! Cells per side of the blocks whose maximum heights a tile keeps.
      static constexpr int kBlockSize = 8;

      /**
       * Raw heights of one tile, for grid traversal (ray / DEM intersection).
       * `vertices` holds the (T + 1) x (T + 1) cell-centre heights from
       * column tileX * T and row tileY * T (the last column and row are the
       * neighbouring tiles' first ones, NaN beyond the DEM), so every cell of
       * the tile has its four corners here. `blockMax` holds, per block of
       * kBlockSize x kBlockSize cells, the highest of its corners; a block or
       * tile with unfilled holes takes the highest valid height of the tile
       * (a hole is taken to reach that high), or +infinity if it has none.
       * Valid until tiles are read again (the cache may drop it).
       */
      struct TileView
      {
        const float *vertices = nullptr;
        int stride = 0;               //!< T + 1
        const float *blockMax = nullptr;
        int blocksPerSide = 0;        //!< T / kBlockSize
        float maxHeight = 0.0f;       //!< over the tile, holes as for blocks
      };
      //! False outside the DEM.
      bool tileView( int tileX, int tileY, TileView &view ) const
      {
        const Tile *t = tile( tileX, tileY );
        if ( !t )
          return false;
        view.vertices = t->vertices.data();
        view.stride = mOptions.tileSize + 1;
        view.blockMax = t->blockMax.data();
        view.blocksPerSide = mOptions.tileSize / kBlockSize;
        view.maxHeight = t->maxHeight;
        return true;
      }

      //! Pixel (column, row) from (x, y) in the DEM's CRS: the inverse geotransform.
      const std::array<double, 6> &inverseGeoTransform() const { return mInverse; }

      //! Horizontal metres per CRS unit near (x, y) along x and y (1 for projected CRSs).
      Eigen::Vector2d metresPerUnit( double x, double y ) const;

      //! Tiles read from the raster so far (a tile read again after the cache dropped it counts again).
      long tileReadCount() const { return mTileReads; }
      //! Cells filled so far (in tiles read so far).
      long filledCellCount() const { return mFilledCells; }
      //! Cells bridged so far (in tiles read so far; DemOptions::bridgeHolesUpToCells).
      long bridgedCellCount() const { return mBridgedCells; }
      //! Holes up to this many cells across are bridged (0: none).
      int bridgeHolesUpToCells() const { return mOptions.bridgeHolesUpToCells; }

      /**
       * Height sigma (m) of the bridged cells under (x, y) in the DEM's CRS:
       * the largest of the four cells interpolated there, 0 where none of
       * them is bridged; nothing where heightAt() has nothing.
       */
      std::optional<double> bridgeSigmaAt( double x, double y ) const;

    private:
      struct Tile
      {
        std::vector<float> vertices; //!< (tileSize + 1)^2, NaN where still empty
        std::vector<float> blockMax; //!< as TileView
        std::vector<float> bridgeSigma; //!< as vertices: the bridged cells' height sigma (m), 0 elsewhere; empty if none
        float maxHeight = 0.0f;      //!< as TileView
        size_t index = 0;            //!< in mIndex (mIndex.size(): in no slot)
        unsigned long lastUse = 0;   //!< mClock at the last use
      };
      //! The tile, read if need be; nothing outside the DEM.
      const Tile *tile( int tileX, int tileY ) const
      {
        if ( tileX < 0 || tileY < 0 || tileX >= mTilesX || tileY >= mTilesY )
          return nullptr;
        Tile *t = mIndex[static_cast<size_t>( tileY ) * mTilesX + tileX];
        if ( !t )
          return readTile( tileX, tileY );
        t->lastUse = ++mClock;
        return t;
      }
      //! Reads, fills and caches a tile of the DEM (in range).
      const Tile *readTile( int tileX, int tileY ) const;
      //! The cells of the DEM read around a tile: width x height from column x0, row y0.
      struct Region
      {
        int x0 = 0, y0 = 0, width = 0, height = 0;
        long filledInTile = 0; //!< cells of the tile the fill gave a height
      };
      /**
       * Reads the tile from cell (x0, y0) with `halo` cells around it into
       * mRegion (`original`, if given, gets it as read), marks the empty
       * cells and fills them (holeFillHalo passes); returns the cells of the
       * tile (and its extra last row and column) left empty.
       */
      long readRegion( int x0, int y0, int halo, Region &at, std::vector<double> *original ) const;
      //! The tile's block maxima and its highest height, from its vertices (tile from cell x0, y0; without holes: faster).
      void setBlockMaxima( Tile &t, int x0, int y0, bool mayHaveHoles ) const;
      /**
       * Most tiles of most DEMs have no hole: where the raster's values are
       * exact as floats (types up to 32 bits), reads the tile's cells
       * straight into its vertices, without the halo the fill would need;
       * false (vertices to be read again) where one of them is a hole or the
       * values are not exact as floats.
       */
      bool readTileCells( int x0, int y0, Tile &t ) const;
      /**
       * Bridges the holes of `region` (filled; rw x rh cells from column rx0,
       * row ry0; `original` as read) that the fill left partly empty, in the
       * tile from (x0, y0), up to bridgeHolesUpToCells across; returns the
       * tile's (T + 1)^2 cells' sigmas, empty if none was bridged.
       */
      std::vector<float> bridgeHoles( std::vector<double> &region, const std::vector<double> &original, int rx0, int ry0, int rw, int rh, int x0, int y0 ) const;
      std::optional<double> heightAtPixel( double px, double py ) const;
      //! The tile's cell corner for pixel (px, py) and the bilinear weights; false outside the DEM.
      bool cellAt( double px, double py, const Tile *&t, size_t &corner, double &fu, double &fv ) const;

      DemOptions mOptions;
      void *mDataset = nullptr;
      std::string mCrsWkt;
      bool mGeographic = false;
      int mWidth = 0, mHeight = 0;
      std::array<double, 6> mGeoTransform {};
      std::array<double, 6> mInverse {};
      std::optional<double> mNoData;
      int mTilesX = 0, mTilesY = 0;
      mutable std::vector<Tile *> mIndex;                //!< per tile, row by row: the cached tile or null
      mutable std::vector<std::unique_ptr<Tile>> mCache; //!< at most cacheTiles; a new tile replaces the least recently used
      mutable unsigned long mClock = 0;
      mutable long mTileReads = 0;
      mutable long mFilledCells = 0;
      mutable long mBridgedCells = 0;
      mutable std::vector<double> mRegion;      //!< a tile's region as read, reused
      mutable std::vector<double> mFillScratch; //!< the hole fill's next pass, reused
      mutable std::vector<float> mColumnMax;    //!< setBlockMaxima's column maxima, reused
      bool mCellsExactAsFloat = false;          //!< the band's values are exact as floats (readTileCells())
  };

} // namespace geostation

#endif // GEOSTATION_DEM_DEM_H
