/***************************************************************************
  roadborders.h - a line along a road's border goes onto the road
  -------------------------------------------------------------------------
  Many roads are a dark band between two narrow bright ones: the gravel
  shoulders, the kerbs, the edge markings. Each border is a band of its
  own, and the extraction, which looks for bands of either polarity, may
  follow one of them where the road itself was not found (a car on the
  road, a start on the border), or the seam between a border and the road.
  Such a line runs a road's half width beside the road's centre line, so
  on the ground it is off by more than the road's half width, and the road
  itself counts as missed.

  Across such a line the profile shows the road: a band touching the
  line's side (or at most a border's width from it), with a narrow band -
  its far border - touching it on its other side, the road at least 1.3
  times as wide. The near border, under the line, need not show as a band
  of its own (merged with the grass beside it, it is one wider band), but
  the line must not lie on a band of the road's own tone that is as wide as
  a road: that is a road beside a road, or beside a strip of field. A line
  that shows this along at least half of its profiles, the road on the
  same side, is moved onto the road's centre (the median of the shifts
  found within a few profiles; bridged across a car, fading out where the
  line leaves the border for a longer stretch, and growing from nothing
  at a junction's end so that the junction holds). A line so moved that
  then runs on other lines along most of its length is that road found
  twice and goes (both shoulders followed); the stretches where it runs on
  another line (at least a road's width long) are cut out of it, and the
  pieces between are lines of their own. Run it after the shoulder
  lines beside a road's own line have been cut out (companionlines.h):
  moved, such a line would run a few pixels beside the road's line, too
  far to be the same line and too near to be another road.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_ROADBORDERS_H
#define GEOSTATION_EXTRACTION_ROADBORDERS_H

#include <vector>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "extraction/polygoncompilation.h"

namespace geostation
{

  struct RoadBorderOptions
  {
    double stepPx = 2.0;          //!< profiles along the line, this far apart
    double roadOverBorder = 1.3;  //!< the road at least this many times as wide as the border the line runs on
    double touchingPx = 2.0;      //!< bands whose edges lie this close touch
    double minShare = 0.5;        //!< of a line's profiles that show it on a road's border (the road on one side), at least, to move it
    int smoothHalfWindow = 5;     //!< a profile's shift: the median of those found within this many profiles either side
    double duplicateShare = 0.7;  //!< a moved line within reach of others along at least this share of its length goes; a shorter stretch on another is cut out
    double toleranceDp = 0.3;     //!< the moved line simplified to this (Douglas-Peucker, px)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct RoadBorderSummary
  {
    std::vector<CompiledPolygon> lines; //!< the lines, those on a border moved onto the road, in their order (duplicates left out, repeats cut)
    int moved = 0;                      //!< lines moved onto the road beside them
    int duplicates = 0;                 //!< of them, left out: the road had a line of its own
    int repeatsCut = 0;                 //!< of them, cut where they ran on another line (the rest kept)
  };

  /**
   * `lines` of the image `grey`, each that runs along a road's border
   * moved onto the road (`object` says what a road looks like; the
   * borders may be narrower than its narrowest road). Reader errors of the
   * image propagate.
   */
  RoadBorderSummary moveBordersOntoRoads( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                          const RoadBorderOptions &options = RoadBorderOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_ROADBORDERS_H
