/***************************************************************************
  companionlines.h - markings, kerbs and shoulders are not roads
  -------------------------------------------------------------------------
  A road is one band, whatever lines run along it: a centre or edge
  marking, a kerb, a bright shoulder between the asphalt and the grass, a
  strip of verge between the road and a field's edge. Each of them is a
  band of its own and may be extracted and verified like a road; beside
  the road it belongs to, it is not one. A line is a companion when most
  of its length runs along wider lines (within 25 degrees), each within
  half their two widths and 2 px - one road or the pieces a road was found
  in; companions are removed from the final lines. Two carriageways of one width are not companions
  of each other, nor is a road crossing a wider one near their junction.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_COMPANIONLINES_H
#define GEOSTATION_EXTRACTION_COMPANIONLINES_H

#include <vector>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "extraction/polygoncompilation.h"

namespace geostation
{

  struct CompanionLineOptions
  {
    double besideFraction = 0.7; //!< of a line's length along wider lines and within reach of them, at least, to be a companion
    double narrowerBy = 0.8;     //!< its width at most this fraction of the wider line's
    double gapPx = 2.0;          //!< beyond half the two widths

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct CompanionLineSummary
  {
    std::vector<CompiledPolygon> lines;  //!< the lines kept, in their order
    std::vector<double> widthsPx;        //!< the band's width along each line kept
    int removed = 0;
  };

  /**
   * `lines` of the image `grey` without their companions (widths measured
   * by measureBand() along each line, densified to 4 px).
   */
  CompanionLineSummary removeCompanionLines( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CompanionLineOptions &options = CompanionLineOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_COMPANIONLINES_H
