/***************************************************************************
  companionlines.h - markings, kerbs and shoulders are not roads
  -------------------------------------------------------------------------
  A road is one band, whatever lines run along it: a centre or edge
  marking, a kerb, a bright shoulder between the asphalt and the grass, a
  strip of verge between the road and a field's edge. Each of them is a
  band of its own and may be extracted and verified like a road; beside
  the road it belongs to, it is not one. A line is a companion when most
  of its length runs along wider lines (within 25 degrees), each within
  half their two widths and 2 px - one road, the pieces a road was found
  in, or the same line where it comes back along the road it ran beside;
  companions are removed from the final lines, and the stretches of a line
  that run beside a wider one are cut out of it. Two carriageways of one width are not companions
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
    double narrowerThanRoads = 1.0; //!< a stretch beside a wider band is cut out of a line where its band is narrower than this fraction of the narrowest road looked for (a road that narrow would not be looked for)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct CompanionLineSummary
  {
    std::vector<CompiledPolygon> lines;  //!< the lines kept, in their order (a line cut: its pieces in order)
    std::vector<double> widthsPx;        //!< the band's width along each line kept (median)
    int removed = 0;                     //!< lines removed whole
    int cut = 0;                         //!< lines whose stretches beside a wider band were removed
  };

  /**
   * `lines` of the image `grey` without their companions. Each line is
   * judged at points 4 px apart, the band's width measured across it where
   * it runs near another line (the median of the measurements over 16 px):
   * a line compiled through a junction may run along a shoulder and then
   * along the road itself. A line is removed whole when at least
   * `besideFraction` of its points run beside wider bands; else the
   * stretches that do (two points or more) and whose band is narrower than
   * `narrowerThanRoads` x the narrowest road looked for are cut out, and
   * each piece left at least twice its width and 12 px long is kept, its
   * cut ends dead ends.
   */
  CompanionLineSummary removeCompanionLines( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CompanionLineOptions &options = CompanionLineOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_COMPANIONLINES_H
