/***************************************************************************
  areaofinterest.h - sample lines across a rectangle (report §4.1, REM)
  -------------------------------------------------------------------------
  The regional extraction method and the verification both look at a
  rectangular area of interest whose main axis follows the expected line.
  Sample lines cross the axis at regular spacing; on each, every point
  gets a confidence (the band response of the expected width over the
  expected contrast); a semi-threshold keeps the few best points of each
  line; an iterative collinearity relaxation raises points that have
  collinear partners on the neighbouring lines and lowers isolated ones;
  and the chain of confirmed points with the highest total confidence is
  the line found in the area.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_AREAOFINTEREST_H
#define GEOSTATION_EXTRACTION_AREAOFINTEREST_H

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  struct AreaOfInterest
  {
    Eigen::Vector2d origin = Eigen::Vector2d::Zero(); //!< start of the main axis (pixelInImage)
    Eigen::Vector2d axis = Eigen::Vector2d::UnitX();  //!< unit direction of the main axis
    double lengthPx = 40.0;
    double halfWidthPx = 12.0;
    double spacingPx = 3.0; //!< between sample lines; line j crosses the axis at (j + 1) * spacing

    int lineCount() const { return std::max( 1, static_cast<int>( lengthPx / spacingPx ) ); }
    //! The point at `offsetPx` across the axis on sample line `line`.
    Eigen::Vector2d pointOn( int line, double offsetPx ) const;
  };

  struct AreaAnalysisOptions
  {
    int polarity = 1;
    double widthPx = 8.0;         //!< expected band width
    double contrast = 20.0;       //!< expected contrast: confidence 1 (grey levels)
    double semiThreshold = 0.35;  //!< confidences below are dropped before relaxation
    int candidatesPerLine = 3;    //!< the semi-threshold keeps at most this many points per line
    int relaxationIterations = 3;
    double confirmThreshold = 0.3; //!< after relaxation
    double maxAngleDeg = 30.0;    //!< between the line and the main axis, and between chain links
    int maxGapLines = 3;          //!< sample lines a chain may skip
  };

  struct AreaCandidate
  {
    double offsetPx = 0.0;
    double confidence = 0.0;
  };

  //! Confirmed candidates per sample line, after the semi-threshold and the relaxation.
  std::vector<std::vector<AreaCandidate>> analyseArea( const cv::Mat &grey, const AreaOfInterest &area, const AreaAnalysisOptions &options,
                                                       const std::optional<double> &startOffsetPx = std::nullopt );

  struct ChainLink
  {
    int line = 0;
    double offsetPx = 0.0;
    double confidence = 0.0;
  };

  /**
   * The chain of candidates with the highest total confidence (a skipped
   * line costs 0.3). With `startOffsetPx` the chain leaves from that point
   * before the first line (REM continuing a line), otherwise it may start
   * anywhere (verification). Empty when nothing is confirmed.
   */
  std::vector<ChainLink> bestChain( const std::vector<std::vector<AreaCandidate>> &lines, const AreaOfInterest &area, const AreaAnalysisOptions &options,
                                    const std::optional<double> &startOffsetPx );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_AREAOFINTEREST_H
