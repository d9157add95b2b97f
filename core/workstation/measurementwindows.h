/***************************************************************************
  measurementwindows.h - the pixels a measurement reads in each view
  -------------------------------------------------------------------------
  An image too large to prepare whole for matching (MatchImageCache's
  maxWholePixels) is matched in windows of it. measurementWindows() says
  which: what proposeConjugates() reads for one click. The windows follow
  the click's epipolar curve, so their size depends on the depth range
  searched and the view geometry, not on the image's size.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_MEASUREMENTWINDOWS_H
#define GEOSTATION_WORKSTATION_MEASUREMENTWINDOWS_H

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "matching/matchingwindows.h"
#include "workstation/pointmeasurer.h"

namespace geostation
{

  struct MeasurementWindowSummary
  {
    //! Per view (image pixels); none for a view that is not oriented or does not see the curve.
    std::vector<std::optional<cv::Rect>> windows;
    /**
     * Views whose window was cut to `maxPixels`: there only the part of the
     * curve around the point predicted on ProposalOptions::groundOfPixel
     * (or around the curve's middle) is searched.
     */
    std::vector<size_t> cut;
  };

  /**
   * The pixels of each view that proposeConjugates( views, reference,
   * pixelInReference, options ) reads (views' `pixels` are not used): in
   * the reference around the click, in every other oriented view around the
   * click's epipolar curve within the frame, widened by the band, the
   * correlation and least-squares windows (stretched by up to
   * AreaMatchOptions::maxAffineScale) and a few pixels of least squares'
   * movement. `imageSizes` are the views' images' sizes (pixels). Throws
   * std::invalid_argument if the reference is out of range or not
   * oriented, the sizes do not go with the views, or maxPixels < 1.
   */
  MeasurementWindowSummary measurementWindows( const std::vector<MeasurementView> &views, const std::vector<cv::Size> &imageSizes, size_t reference,
      const Eigen::Vector2d &pixelInReference, const ProposalOptions &options, long long maxPixels );

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_MEASUREMENTWINDOWS_H
