/***************************************************************************
  lineprofile.h - the road line across its direction (thesis §6.1, §6.5.1)
  -------------------------------------------------------------------------
  locateLine() finds the line on a grey-level profile sampled across its
  direction: the centre of a stripe (half-contrast centroid) or the
  steepest point of an edge of the right polarity (parabola on the
  derivative), to a fraction of a pixel. analyseSeed() turns an operator's
  click into a start: the line nearest the click, what kind it is, and its
  direction (from the operator, or measured along the line).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_LINEPROFILE_H
#define GEOSTATION_TRACING_LINEPROFILE_H

#include <optional>
#include <string>

#include "tracing/linetrace.h"

namespace geostation
{

  struct LineHit
  {
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< on the line
    double offsetPx = 0.0;   //!< from the sampling centre, along the right-hand normal
    double contrast = 0.0;   //!< as LineProfile::contrast
    double widthPx = 0.0;    //!< stripes: full width at half contrast
    double sigmaPx = 0.5;    //!< across the line
  };

  struct LocateOptions
  {
    double searchHalfPx = 4.0;   //!< how far across the line to look, each side
    double minContrast = 6.0;    //!< grey levels
    int alongSamples = 3;        //!< profiles averaged along the line (1 px apart)
    double maxWidthRatio = 2.2;  //!< stripes: width at most r times the expected width
    double minWidthRatio = 2.2;  //!< stripes: width at least 1/r of the expected width (larger where the line may narrow with distance)
    double noiseGrey = 2.0;      //!< grey-level noise assumed for sigmaPx
  };

  /**
   * The line of `profile` on the profile through `centre` across `direction`
   * (unit, pixel space): the candidate nearest the centre. Nothing when no
   * candidate is within options.searchHalfPx or it is too weak.
   */
  std::optional<LineHit> locateLine( const cv::Mat &grey, const Eigen::Vector2d &centre, const Eigen::Vector2d &direction, const LineProfile &profile,
                                     const LocateOptions &options );

  struct SeedOptions
  {
    double searchRadiusPx = 8.0;  //!< "no edge within N px of the seed"
    double minContrast = 10.0;    //!< grey levels
    double maxStripeWidthPx = 60.0;
    int directionWindow = 21;     //!< structure-tensor window when no direction is given
  };

  struct SeedAnalysis
  {
    enum class Status
    {
      Ok,
      OutsideImage, //!< the click is not on the image
      NoLine,       //!< no edge or painted line within SeedOptions::searchRadiusPx of it
    };
    Status status = Status::NoLine;
    std::string message;          //!< one sentence when not ok
    bool ok() const { return status == Status::Ok; }
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< snapped onto the line
    Eigen::Vector2d direction = Eigen::Vector2d( 0, -1 );
    LineProfile profile;
  };

  /**
   * The line nearest an operator's click: of the stripes of each kind the
   * strongest, or one nearer the click with at least 75 % of its contrast;
   * then the nearest of those and the edges (a stripe wins a near tie).
   * With no `directionDeg` the direction is measured (structure tensor,
   * then the line located along it over +-24 px) and points up the image
   * (Xin's (1995) 0 degrees default) or, for a line nearly along the rows,
   * to the right. Where the line is found at fewer than 6 of the 8
   * positions along that direction (a crack or a worn notch at the click
   * turns the tensor), the directions every 15 degrees are tried and the
   * one along which a line of at least 70 % of the contrast is found
   * furthest is taken (found at all 8 positions, half the contrast will do).
   * Where no line at the click is found at more than 3 of them (the click
   * lies on a crack or a worn patch longer than that), the line found 12-24
   * px along a direction either way that runs through the click is taken,
   * snapped to the click's place along it.
   */
  SeedAnalysis analyseSeed( const cv::Mat &grey, const Eigen::Vector2d &seedPixel, std::optional<double> directionDeg, const SeedOptions &options = SeedOptions() );

  //! Mean grey levels on each side of a line (of the direction of travel), beside it.
  struct LineSides
  {
    double left = 0.0;
    double right = 0.0;
    double contrast = 0.0; //!< an edge's step between its sides; a stripe's centre against its sides' mean
  };

  /**
   * The grey levels beside the line through `pixelInImage` along `direction`
   * (unit): an edge's 3 to 6 px out, a stripe's 2 to 5 px beyond its half
   * width, each side averaged over 3 profiles 1 px apart; and the line's
   * contrast there. Nothing near the image's border.
   */
  std::optional<LineSides> lineSides( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, const LineProfile &profile );

  /**
   * Whether a line with sides `seen` can be the line with sides `reference`
   * under other light (a shadow, a sunlit patch): both sides scaled by one
   * gain between 0.4 and 2.5 agree with the reference's within `toleranceGrey`.
   */
  bool sidesAgree( const LineSides &reference, const LineSides &seen, double toleranceGrey );

  //! The options a follower uses to locate a line of `profile` (contrast threshold from the seed's contrast).
  LocateOptions locateOptionsFor( const LineProfile &profile, const FollowOptions &follow, double searchHalfPx );

} // namespace geostation

#endif // GEOSTATION_TRACING_LINEPROFILE_H
