/***************************************************************************
  crossprofile.h - grey-level profiles across a line object (report §4.1)
  -------------------------------------------------------------------------
  A road in an aerial image is a band from one to some tens of pixels
  wide, fairly uniform inside (markings and cars aside), with two roughly
  parallel borders: brighter or darker than both sides, or - polarity 0,
  the default - either, side by side: asphalt darker than a bright field
  on one side and brighter than a wood on the other. Such a band, between
  a darker and a brighter side, must show a plateau at least 3 px wide,
  or the ramp of any blurred edge between two fields would be one. Every stage of the
  extraction - starting points, LEM, REM, verification - decides on
  profiles sampled across the band: the band's centre, width, contrast
  (the smaller of its two sides, grey levels) and the variation inside.

  Frames: pixelInImage = (col, row) as docs/conventions.md §1 (pixel (i, j) covers
  [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5)); a direction is a unit vector (col, row) along the line, its
  normal n = (-dir.row, dir.col) points to the line's left when row runs
  down (the right of the direction of travel on screen).
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_CROSSPROFILE_H
#define GEOSTATION_EXTRACTION_CROSSPROFILE_H

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  //! The report's extraction parameters: what a line object looks like.
  struct LineObjectOptions
  {
    int polarity = 0;           //!< +1: brighter than both sides, -1: darker than both, 0: either, side by side
    double minContrast = 15.0;  //!< grey levels: both sides at least this much darker (polarity applied)
    double maxVariation = 14.0; //!< spread of the grey levels inside the band (robust: 1.4826 x median absolute deviation)
    double minWidthPx = 4.0;    //!< from 1 (a line one pixel wide: brighter or darker than both sides)
    double maxWidthPx = 24.0;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  //! A band found on a profile.
  struct CrossSection
  {
    double offsetPx = 0.0;  //!< centre, along the profile from its origin (pixels)
    double widthPx = 0.0;   //!< between the half-contrast crossings
    double contrast = 0.0;  //!< the smaller side's contrast, polarity applied (grey levels)
    double variation = 0.0; //!< robust spread inside (grey levels; markings and cars hardly count)
    int tone = 0;           //!< +1 brighter than both sides, -1 darker than both, 0 between a darker and a brighter side
  };

  /**
   * Grey values (polarity applied: multiplied by profileSign(polarity)) sampled by
   * bilinear interpolation at centre + t n for t = -halfLength .. +halfLength
   * (1 px apart), each the mean of `alongSamples` samples spread over
   * +-alongHalfPx along `direction`. Samples off the image are NaN.
   */
  std::vector<double> sampleCrossProfile( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction,
                                          int halfLength, int polarity, double alongHalfPx = 0.0, int alongSamples = 1 );

  /**
   * Bands of width widthMinPx..widthMaxPx on a profile from
   * sampleCrossProfile() whose both sides are at least `minContrast` darker
   * (polarity applied) and whose inside varies at most `maxVariation`
   * (robust spread); overlapping candidates suppressed, strongest first.
   * `polarity` 0 (the profile's grey levels as sampled): each side's
   * contrast in either sign, a band between a darker and a brighter side
   * only where it shows a plateau (at least 3 samples, its halves within
   * 15 % of the contrast of each other).
   * Offsets are relative to the profile's centre sample. `oneSided`: one
   * side suffices and the other need only not be darker by more than a
   * third of the minimum contrast (where another road joins, the band opens
   * on that side).
   */
  std::vector<CrossSection> findCrossSections( const std::vector<double> &profile, double widthMinPx, double widthMaxPx,
                                               double minContrast, double maxVariation, bool oneSided = false, int polarity = 1 );

  /**
   * Band response of a fixed width at every sample of the profile: the
   * smaller side's contrast (polarity applied) of a band `widthPx` wide
   * centred there, NaN where the band or its sides leave the profile.
   * `polarity` 0: the smaller side's contrast in either sign where both
   * sides differ in the same sign, 0 where they differ in opposite signs.
   */
  std::vector<double> bandResponse( const std::vector<double> &profile, double widthPx, int polarity = 1 );

  //! The factor sampleCrossProfile() applies: the polarity, or +1 for 0 (either).
  inline int profileSign( int polarity ) { return polarity == 0 ? 1 : polarity; }

  //! The normal of a direction: (-dir.row, dir.col).
  inline Eigen::Vector2d normalOf( const Eigen::Vector2d &direction ) { return Eigen::Vector2d( -direction.y(), direction.x() ); }

  //! Bilinear grey value (CV_8UC1) at pixelInImage, NaN outside the outermost pixel centres.
  double greyAt( const cv::Mat &grey, double col, double row );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_CROSSPROFILE_H
