/***************************************************************************
  centrerefinement.h - the final lines moved onto the band's centre
  -------------------------------------------------------------------------
  The final polygons are compiled from the result matrix: they run through
  pixel centres and are straightened to 0.75 px, so a line's course can be
  a pixel or more off the band's centre, which on the ground is the 3-D
  line's error. This final step (after §4.5's final processing) samples
  the grey-level profile across each line every couple of pixels and takes
  the centre of the band nearest the line (between its half-contrast
  crossings) where the band has the line's own width (a car on the road or
  a shadow over half of it changes the width there). Each sample is then
  moved onto a quadratic fitted along the line through the centres found
  within a few profiles of it, fitted again without those it leaves far
  off: a kink the line took round a car is straightened by the centres on
  either side. A short stretch where no centre was found runs straight
  between its moved ends; a longer one keeps its course. The ends at an
  intersection go where the branches, moved, cross (the point nearest the
  straight lines fitted to each branch beyond the intersection's reach),
  so they still meet, and the line's own move grows from nothing there to
  full over half the widest road's width.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_CENTREREFINEMENT_H
#define GEOSTATION_EXTRACTION_CENTREREFINEMENT_H

#include <utility>
#include <vector>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "extraction/polygoncompilation.h"

namespace geostation
{

  struct CentreRefinementOptions
  {
    double stepPx = 2.0;        //!< profiles along the line, this far apart
    double searchPx = 2.5;      //!< the band's centre within this of the line
    double widthTolerance = 0.15;  //!< a profile counts where the band's width is within this fraction of the line's median width
    double widthTolerancePx = 1.0; //!< ... or within this many pixels
    int fitHalfWindow = 5;      //!< the centres of this many profiles either side are fitted (a quadratic along the line)
    int minSupport = 4;         //!< profiles that found the band within the fit's window, else the stretch is bridged
    double toleranceDp = 0.3;   //!< the moved line simplified to this (Douglas-Peucker, px)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct CentreRefinementSummary
  {
    std::vector<CompiledPolygon> lines; //!< the lines moved, in the same order, ends and symbols unchanged
    int profiles = 0;                   //!< profiles taken
    int bandFound = 0;                  //!< of them, where the band of the line's width was found near it
    double meanShiftPx = 0.0;           //!< mean |shift| applied over all profiles
    //! Each intersection the lines' ends met at (pixelInImage) and where it went: where its branches, moved, cross.
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> junctions;

    //! `intersections` (compilation's centres), each where its lines' ends went (within 2 px of one here), else as it was.
    std::vector<Eigen::Vector2d> movedIntersections( const std::vector<Eigen::Vector2d> &intersections ) const;
  };

  /**
   * Moves each line of `lines` onto the centre of its band in `image`
   * (the lines' own image; `object` says what a band looks like). Reader
   * errors of the image propagate.
   */
  CentreRefinementSummary refineLineCentres( const GreyTiles &image, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CentreRefinementOptions &options = CentreRefinementOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_CENTREREFINEMENT_H
