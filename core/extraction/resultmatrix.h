/***************************************************************************
  resultmatrix.h - the raster record of what was extracted (report §3, §4.2)
  -------------------------------------------------------------------------
  One byte per image pixel: S a starting point, * a LEM segment, + a REM
  segment (not yet verified); I extracted in this image and verified in
  the partner, E extracted in the partner and verified here. Lines are
  drawn one pixel wide, 8-connected, through the pixels their vertices
  fall in (pixelInImage as docs/conventions.md §1: pixel (c, r) covers
  [c, c+1) x [r, r+1), its centre is (c + 0.5, r + 0.5)).

  The maximum-length polygons compiled from it: polygoncompilation.h.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_RESULTMATRIX_H
#define GEOSTATION_EXTRACTION_RESULTMATRIX_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  class ResultMatrix
  {
    public:
      static constexpr uint8_t kStart = 'S', kLocal = '*', kRegional = '+', kInternal = 'I', kExternal = 'E';

      ResultMatrix() = default;
      ResultMatrix( int width, int height );

      int width() const { return mSymbols.cols; }
      int height() const { return mSymbols.rows; }
      uint8_t at( int col, int row ) const;
      const cv::Mat &symbols() const { return mSymbols; }

      /**
       * The part `rect` (clipped) of this matrix, sharing its pixels, in
       * coordinates whose origin is `origin` of this matrix (pixelInWindow =
       * pixelInImage - origin): what a sub-image's extraction reads, in the
       * coordinates of its grey window, a little beyond that window.
       */
      ResultMatrix view( const cv::Rect &rect, const cv::Point &origin ) const;

      /**
       * Draws the polyline with `symbol`; pixels already holding a symbol
       * keep it unless `overwrite`. Pixels off the matrix are skipped.
       */
      void drawPolyline( const std::vector<Eigen::Vector2d> &pixelsInImage, uint8_t symbol, bool overwrite = false );

      /**
       * The nearest pixel within `radiusPx` of `pixelInImage` holding any of
       * `symbols` (all symbols when empty), or nothing.
       */
      std::optional<Eigen::Vector2i> nearestSymbol( const Eigen::Vector2d &pixelInImage, double radiusPx, const std::string &symbols = std::string() ) const;

      //! Clears every pixel holding one of `symbols`.
      void erase( const std::string &symbols );

      //! Pixels holding one of `symbols`.
      long count( const std::string &symbols ) const;

    private:
      cv::Mat mSymbols; // CV_8UC1
      cv::Point mShift; // a view's coordinates of its first pixel
  };

  //! Polyline length in pixels.
  double polylineLength( const std::vector<Eigen::Vector2d> &polyline );

} // namespace geostation

#include "extraction/polygoncompilation.h"

#endif // GEOSTATION_EXTRACTION_RESULTMATRIX_H
