/***************************************************************************
  crossprofile.h - grey-level profiles across a line object (report §4.1)
  -------------------------------------------------------------------------
  A road in an aerial image is a band a few pixels wide, brighter (or
  darker) than both sides, fairly uniform inside. Every stage of the
  extraction - starting points, LEM, REM, verification - decides on
  profiles sampled across the band: the band's centre, width, contrast
  (the smaller of its two sides, grey levels) and the variation inside.

  Frames: pixelInImage = (col, row) as CONVENTIONS §1 (pixel (i, j) covers
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
    int polarity = 1;           //!< +1: brighter than its surroundings, -1: darker
    double minContrast = 15.0;  //!< grey levels: both sides at least this much darker (polarity applied)
    double maxVariation = 14.0; //!< spread of the grey levels inside the band (robust: 1.4826 x median absolute deviation)
    double minWidthPx = 4.0;
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
  };

  /**
   * Grey values (polarity applied: multiplied by `polarity`) sampled by
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
   * Offsets are relative to the profile's centre sample. `oneSided`: one
   * side suffices and the other need only not be darker by more than a
   * third of the minimum contrast (where another road joins, the band opens
   * on that side).
   */
  std::vector<CrossSection> findCrossSections( const std::vector<double> &profile, double widthMinPx, double widthMaxPx,
                                               double minContrast, double maxVariation, bool oneSided = false );

  /**
   * Band response of a fixed width at every sample of the profile: the
   * smaller side's contrast (polarity applied) of a band `widthPx` wide
   * centred there, NaN where the band or its sides leave the profile.
   */
  std::vector<double> bandResponse( const std::vector<double> &profile, double widthPx );

  //! The normal of a direction: (-dir.row, dir.col).
  inline Eigen::Vector2d normalOf( const Eigen::Vector2d &direction ) { return Eigen::Vector2d( -direction.y(), direction.x() ); }

  //! Bilinear grey value (CV_8UC1) at pixelInImage, NaN outside the outermost pixel centres.
  double greyAt( const cv::Mat &grey, double col, double row );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_CROSSPROFILE_H
