/***************************************************************************
  linestate.h - where a line extraction stands, and where it stopped
  -------------------------------------------------------------------------
  LEM and REM hand each other a LineState (the last point, the direction
  of travel and the line's measured width and contrast); every stop is a
  DeadEnd of one of Kazmierczak et al.'s (1983) kinds (§3).
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_LINESTATE_H
#define GEOSTATION_EXTRACTION_LINESTATE_H

#include <string>

#include <Eigen/Core>

namespace geostation
{

  struct LineState
  {
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    Eigen::Vector2d direction = Eigen::Vector2d::UnitX(); //!< unit, (col, row), direction of travel
    double widthPx = 8.0;
    double contrast = 20.0; //!< grey levels, polarity applied
    /**
     * The band's tone where it was last measured: +1 brighter than both
     * sides, -1 darker than both, 0 between a darker and a brighter side
     * or not known. A line does not pass from a band of one tone to one of
     * the other in a step (from the asphalt onto its bright shoulder); it
     * may through a stretch between (a road passing from a bright field
     * into a dark wood).
     */
    int tone = 0;
  };

  enum class DeadEndKind
  {
    ImageBorder,   //!< final: the line leaves the image
    KnownRoad,     //!< final: the line runs into a line already extracted (joined to it)
    BreakOff,      //!< LEM stopped at a distortion; REM takes over
    FinalBreakOff, //!< REM found no continuation either
    Ideal,         //!< REM reached a stretch LEM can follow again
    Verification,  //!< end of an accepted part near the end of the verified polygon: continue extracting here
    Unverified,    //!< final: verification did not confirm the line beyond here
    SubImageBorder, //!< temporary: the line leaves the sub-image; continued in the adjacent one
  };

  //! "image_border", "known_road", "break_off", "final_break_off", "ideal", "verification", "unverified", "sub_image_border"
  std::string deadEndKindName( DeadEndKind kind );

  struct DeadEnd
  {
    LineState state; //!< direction points out of the line, where it would continue
    DeadEndKind kind = DeadEndKind::FinalBreakOff;
  };

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_LINESTATE_H
