/***************************************************************************
  verification.h - a line of one image confirmed in its partner (§4.4.1)
  -------------------------------------------------------------------------
  Each maximum-length polygon extracted in the source image is mapped into
  the target image and checked there by a modified REM: areas of interest
  laid symmetrically along the mapped polygon, as wide as the mapping's
  misregistration, and in each the chain of highest confidence anywhere
  in the area (not necessarily from its centre). Once the line is found,
  the next area follows its offset from the mapped polygon, but never
  beyond the misregistration (tracking must not walk off onto a line
  beside the mapped one); after a miss the search starts again around the
  mapped polygon. The polygon is
  accepted wholly, in parts, or not at all: the accepted parts of the
  source polygon (the stretch the found line covers, projected onto the
  mapped polygon) and the line found in the target are returned together.
  An accepted part that reaches to within a few pixels of the polygon's end
  leaves a verification dead end there (extraction continues in the target
  image); other ends are final.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_VERIFICATION_H
#define GEOSTATION_EXTRACTION_VERIFICATION_H

#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "extraction/linestate.h"
#include "extraction/resultmatrix.h"

namespace geostation
{

  struct VerificationOptions
  {
    double misregistrationPx = 12.0; //!< the mapping's error the search allows: half-width of the first areas, and how far from the mapped polygon any area reaches
    double trackingHalfWidthPx = 4.0; //!< half-width around the line once it is found (within the misregistration)
    double areaLengthPx = 40.0;
    double minChainConfidence = 0.5;  //!< mean confidence of a chain to accept
    int minChainLinks = 3;
    double maxAngleDeg = 20.0;
    double deadEndReachPx = 8.0;      //!< "a few pixels": an accepted part this close to the polygon's end leaves a verification dead end
    double densifyPx = 2.0;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct VerifiedPart
  {
    std::vector<Eigen::Vector2d> inSource; //!< the accepted stretch of the source polygon (source pixels)
    std::vector<Eigen::Vector2d> inTarget; //!< the line found in the target image (target pixels)
  };

  struct VerificationSummary
  {
    std::vector<VerifiedPart> accepted;
    std::vector<DeadEnd> continueFrom; //!< verification dead ends, in the target image, pointing outwards
    std::vector<DeadEnd> finalDeadEnds; //!< in the target image
    int wholly = 0, partly = 0, rejected = 0;
    double sourceLengthPx = 0.0, acceptedSourceLengthPx = 0.0;
    double seconds = 0.0;
  };

  //! Source pixel -> target pixel (nothing where undefined).
  using PixelMap = std::function<std::optional<Eigen::Vector2d>( const Eigen::Vector2d & )>;

  /**
   * Verifies `polygons` of the source image in the target image. The band's
   * width and contrast are measured on the source image along each polygon.
   */
  VerificationSummary verifyPolygons( const GreyTiles &sourceGrey, const GreyTiles &targetGrey, const std::vector<CompiledPolygon> &polygons,
                                      const PixelMap &sourceToTarget, const LineObjectOptions &object, const VerificationOptions &options );

  //! The same for images held in memory (CV_8UC1).
  VerificationSummary verifyPolygons( const cv::Mat &sourceGrey, const cv::Mat &targetGrey, const std::vector<CompiledPolygon> &polygons,
                                      const PixelMap &sourceToTarget, const LineObjectOptions &object, const VerificationOptions &options );

  /**
   * The band of `object` across `direction` at `pixelInImage` of `grey`
   * nearest it, within 3 px; nothing where there is none.
   */
  std::optional<CrossSection> bandAt( const GreyTiles &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, const LineObjectOptions &object );

  //! How much of a line its band carries, and whether the band keeps its width along it (bandSupport()).
  struct BandSupport
  {
    double share = 1.0;    //!< of the line's samples, every 2 px (beyond the trimmed mouths), where bandAt() finds a band
    double widening = 1.0; //!< the band's width at one end of the stretch found over that at the other, where it changes steadily (else 1)
  };

  /**
   * How much of `line` (pixelInImage) the band of `object` carries: the
   * fraction of its samples, every 2 px, where bandAt() finds a band. A road
   * shows its band nearly everywhere but where a car, a shadow or a junction
   * interrupts it; a chain through the grain of a field or a row of trees
   * finds one only here and there. `trimStart` / `trimEnd`: the line ends
   * there at a junction, and the samples within twice the band's width of
   * it (the median width found), whose profiles cross the other road, do
   * not count. Share 1 for a line shorter than 4 px or trimmed away.
   *
   * And how its width changes: a road keeps its width, or changes it at a
   * junction, a lane added, a car; a strip of field converging on a road
   * (between the road and a field's border) widens steadily along the line
   * - `widening` is the ratio of the widths at the ends of a straight line
   * fitted to them, where they follow one (RMS within 15 % of their mean)
   * over at least 4 widths.
   */
  BandSupport bandSupport( const GreyTiles &grey, const std::vector<Eigen::Vector2d> &line, const LineObjectOptions &object, bool trimStart = false,
                           bool trimEnd = false );

  /**
   * The band's width and contrast along a line of `grey` (medians of up to
   * 7 profiles, bandAt() the line); where none is found, the middle of the
   * object's widths and 1.5 x its minimum contrast.
   */
  std::pair<double, double> measureBand( const GreyTiles &grey, const std::vector<Eigen::Vector2d> &line, const LineObjectOptions &object );

  //! The polyline resampled every `stepPx` (its vertices and ends kept).
  std::vector<Eigen::Vector2d> densifyPolyline( const std::vector<Eigen::Vector2d> &polyline, double stepPx );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_VERIFICATION_H
