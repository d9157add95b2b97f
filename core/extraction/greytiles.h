/***************************************************************************
  greytiles.h - an image's grey levels, one window at a time (report §4:
  sub-images)
  -------------------------------------------------------------------------
  The extraction reads its images through GreyTiles, never whole: either
  the image is held in memory (a window is then a view of it, nothing is
  copied), or it is read through a Reader (a raster file) in tiles of
  256 x 256 pixels kept in a least-recently-used cache of bounded size.
  A window of a tile-read image is assembled from its tiles.

  A GreyWindow carries its origin: pixelInImage = pixelInWindow + origin
  (pixelInImage as docs/conventions.md §1). Not thread-safe: one GreyTiles per
  thread.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_GREYTILES_H
#define GEOSTATION_EXTRACTION_GREYTILES_H

#include <cstddef>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  struct GreyWindow
  {
    cv::Mat pixels;   //!< CV_8UC1; empty when the window lies off the image
    cv::Point origin; //!< the window's top-left pixel in the image

    Eigen::Vector2d toWindow( const Eigen::Vector2d &pixelInImage ) const { return pixelInImage - Eigen::Vector2d( origin.x, origin.y ); }
    Eigen::Vector2d toImage( const Eigen::Vector2d &pixelInWindow ) const { return pixelInWindow + Eigen::Vector2d( origin.x, origin.y ); }
    cv::Rect rect() const { return cv::Rect( origin, pixels.size() ); }
  };

  class GreyTiles
  {
    public:
      //! Returns the grey levels (CV_8UC1) of a rectangle of the image, exactly its size; throws on a read error.
      using Reader = std::function<cv::Mat( const cv::Rect &pixels )>;
      static constexpr int kTilePx = 256;

      //! The whole image in memory (CV_8UC1, shared, not copied). Throws std::invalid_argument otherwise.
      explicit GreyTiles( const cv::Mat &grey );

      /**
       * An image of `size` read through `reader` tile by tile; at most
       * `maxCachedBytes` of tiles are kept (at least one window's worth is
       * always allowed). Throws std::invalid_argument for an empty size or
       * no reader.
       */
      GreyTiles( cv::Size size, Reader reader, size_t maxCachedBytes = size_t( 96 ) << 20 );

      cv::Size size() const { return mSize; }
      int width() const { return mSize.width; }
      int height() const { return mSize.height; }
      //! Whether the image is held whole in memory.
      bool whole() const { return !mWhole.empty(); }

      /**
       * The pixels of `rect`, clipped to the image. A view of the image when
       * it is held whole, else a copy assembled from cached tiles (read as
       * needed). Reader errors propagate.
       */
      GreyWindow window( const cv::Rect &rect ) const;

      //! The window of pixels within `radiusPx` of a point (clipped to the image).
      GreyWindow around( const Eigen::Vector2d &pixelInImage, int radiusPx ) const;

      //! The window holding a rectangle of image coordinates widened by `marginPx` (clipped).
      GreyWindow covering( const Eigen::Vector2d &lowerPx, const Eigen::Vector2d &upperPx, int marginPx ) const;

      long tilesRead() const { return mTilesRead; }
      size_t cachedBytes() const { return mCachedBytes; }
      size_t peakCachedBytes() const { return mPeakCachedBytes; }

    private:
      using TileKey = std::pair<int, int>; // (tile row, tile column)
      const cv::Mat &tile( const TileKey &key ) const;

      cv::Size mSize;
      cv::Mat mWhole;
      Reader mReader;
      size_t mMaxCachedBytes = 0;
      mutable std::list<TileKey> mRecent; // most recent first
      mutable std::map<TileKey, std::pair<cv::Mat, std::list<TileKey>::iterator>> mTiles;
      mutable size_t mCachedBytes = 0, mPeakCachedBytes = 0;
      mutable long mTilesRead = 0;
  };

  class RasterReader;

  /**
   * A raster (grey, RGB or palette; 8- or 16-bit) read tile by tile, its grey
   * levels as MatchImage makes them of the whole image: RGB to grey, and a
   * 16-bit image scaled by `range16`, its whole grey range (greyRangeOf(),
   * computed here when not given).
   */
  GreyTiles greyTilesOf( std::shared_ptr<const RasterReader> reader, const std::optional<std::pair<double, double>> &range16 = std::nullopt,
                         size_t maxCachedBytes = size_t( 96 ) << 20 );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_GREYTILES_H
