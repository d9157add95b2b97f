/***************************************************************************
  resultmatrix.h - the raster record of what was extracted (report §3, §4.2)
  -------------------------------------------------------------------------
  One byte per image pixel: S a starting point, * a LEM segment, + a REM
  segment (not yet verified); I extracted in this image and verified in
  the partner, E extracted in the partner and verified here. Lines are
  drawn one pixel wide, 8-connected, through the pixels their vertices
  fall in (pixelInImage as CONVENTIONS §1: pixel (c, r) covers
  [c, c+1) x [r, r+1), its centre is (c + 0.5, r + 0.5)).

  Maximum-length polygon compilation (§4.2) follows the strings of chosen
  symbols: 3 x 3 neighbourhoods tell a dead end (one neighbour), the line's
  run (two) and an intersection (more); the pixels of an intersection are
  examined together (the report's 5 x 5 crossing examination) so that its
  branches leave from one node. Each polygon runs between two dead ends,
  two intersections, or one of each, without an intersection inside.
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
  };

  //! How a compiled polygon ends.
  enum class PolygonEnd
  {
    DeadEnd,
    Intersection,
  };

  struct CompiledPolygon
  {
    std::vector<Eigen::Vector2d> pixels; //!< vertices through the pixel centres (Douglas-Peucker, 0.75 px), ends included (an intersection's end at its centre)
    PolygonEnd startEnd = PolygonEnd::DeadEnd, endEnd = PolygonEnd::DeadEnd;
    std::string symbols; //!< the distinct symbols along it, in order of first appearance (e.g. "I", "IE")
  };

  struct CompilationSummary
  {
    std::vector<CompiledPolygon> polygons;
    std::vector<Eigen::Vector2d> intersections; //!< centres of the intersections (pixelInImage)
  };

  /**
   * Maximum-length polygons of the strings of `symbols` in the matrix;
   * polygons shorter than `minPixels` pixels are dropped (stubs). With
   * `erase`, the compiled symbols are cleared from the matrix.
   */
  CompilationSummary compileMaxLengthPolygons( ResultMatrix &matrix, const std::string &symbols, bool erase, int minPixels = 3 );

  //! Polyline length in pixels.
  double polylineLength( const std::vector<Eigen::Vector2d> &polyline );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_RESULTMATRIX_H
