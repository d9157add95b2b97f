/***************************************************************************
  linerelocation.h - a traced point put back onto the line, averaged along it
  -------------------------------------------------------------------------
  A follower's pixels stray from the line by a pixel or two where it
  starts, bends or bridges worn paint, and a vertex inherits that error
  whole: the reference point defines the ray. Worn paint also moves a
  stripe's centre on any single profile: where the asphalt shows through
  along one side, the visible paint is narrower and its centre lies off
  the line by up to half the missing width, over patches of a few
  decimetres. The images of the stations before see the same line
  10-30 m away, where a few profiles along it already span metres of road,
  and there the centre is good to a few tenths of a pixel.

  relocateOnLine() therefore locates the line across a point on a profile
  averaged along the line over a fixed length on the ground (`windowM`),
  whatever the range: a near image gets as many profiles as that length
  covers there. Both images of a station are relocated with the same
  ground window, so both see the same stretch of paint and a remaining
  wear offset moves the vertex sideways on the road, not in depth.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_LINERELOCATION_H
#define GEOSTATION_TRACING_LINERELOCATION_H

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "geometry/windowshape.h"
#include "tracing/lineprofile.h"
#include "tracing/stereolinematcher.h"

namespace geostation
{

  struct LineRelocation
  {
    LineProfile profile;            //!< the line's kind, polarity, contrast (and width, when widthTimesRange is 0)
    double widthTimesRange = 0.0;   //!< stripes: width (px) x ground range (m), so the width at any range; 0: the profile's
    double searchHalfPx = 3.0;      //!< the line is looked for this far either side of the point
    double windowM = 1.0;           //!< profiles averaged along this length of line on the ground
    int maxAlongSamples = 61;       //!< at most this many profiles (1 px apart)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  /**
   * The line across `pixelInImage` in `image` (`direction`: the line's
   * direction there, unit), with the profiles averaged over
   * relocation.windowM of line: `pxPerM` is the line's scale there (pixels
   * per metre along it) and `rangeM` the ground range, for a stripe's
   * width. Nothing when the line is not found within searchHalfPx.
   */
  std::optional<LineHit> relocateOnLine( const StereoImage &image, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, double pxPerM,
                                         double rangeM, const LineRelocation &relocation );

  /**
   * Interval points of a followed line put back onto the line in their own
   * image (relocateOnLine(), the scale and range from `groundOfPixel` at
   * the point and its neighbours), each taking the located line's sigma.
   * A point where the line is not found stays where it is. Returns how
   * many moved.
   */
  int recentreOnLine( const StereoImage &image, std::vector<Eigen::Vector2d> &points, std::vector<double> &sigmasPx, const GroundOfPixel &groundOfPixel,
                      const LineRelocation &relocation );

} // namespace geostation

#endif // GEOSTATION_TRACING_LINERELOCATION_H
