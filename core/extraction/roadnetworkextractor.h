/***************************************************************************
  roadnetworkextractor.h - a road network from a stereo pair, end to end
  -------------------------------------------------------------------------
  What geostation:extract_roads runs: the pair's registration (through the
  orientation with a DEM or a mean terrain height - estimated by matching
  a grid of points when neither is given - or from control-point pairs),
  the coincident extraction with verification, and, for an oriented pair,
  the 3-D lines.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_ROADNETWORKEXTRACTOR_H
#define GEOSTATION_EXTRACTION_ROADNETWORKEXTRACTOR_H

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "extraction/coincidentextraction.h"
#include "extraction/networkintersection.h"
#include "extraction/pairmapping.h"
#include "extraction/pairmatchwindows.h"
#include "extraction/terrainheight.h"
#include "io/rasterfile.h"
#include "geometry/projection.h"
#include "matching/matchimage.h"

namespace geostation
{

  enum class ControlMapping
  {
    Projective,
    Multiquadric,
  };

  struct RoadNetworkOptions
  {
    CoincidentExtractionOptions coincident;
    NetworkIntersectionOptions network;
    TerrainHeight terrain;               //!< a DEM, when given (oriented pairs)
    std::optional<double> meanHeightM;   //!< otherwise, or where the DEM has no height; estimated when absent
    std::vector<ControlPair> control;    //!< an unoriented pair: registration from these pairs
    ControlMapping controlMapping = ControlMapping::Multiquadric;
    /**
     * The minimum contrast from the image's texture: at least this many
     * times textureGrey() of the first image (and at least
     * coincident.extraction.object.minContrast); 0: not from the texture.
     * On grass with a coarse grain, bands of any width a little brighter or
     * darker than their sides are everywhere; a road stands out of its land
     * by more.
     */
    double contrastPerTexture = 0.0;
    //! An oriented pair: the roads' widths on the ground (metres, narrowest and widest), which with the ground pixel set the widths in pixels (coincident.extraction.object's are then not used)
    std::optional<std::pair<double, double>> roadWidthM;
    //! false: only the pair's set-up - terrain height, overlap, widths in pixels, minimum contrast - in the summary, nothing extracted
    bool extract = true;
  };

  /**
   * What extract_roads uses when given nothing: roads of either polarity,
   * side by side (LineObjectOptions::polarity 0), 3 to 30 m wide on the
   * ground (an oriented pair), the minimum contrast 1.8 x the texture.
   */
  RoadNetworkOptions defaultRoadNetworkOptions();

  //! The widths in pixels that road widths in metres come to (widthsPxFor()).
  struct RoadWidthsPx
  {
    double groundPixelM = 0.0; //!< at the first image's centre, at the terrain height
    double minPx = 0.0, maxPx = 0.0;
    bool clamped = false; //!< the widths in metres reach beyond 1 .. kMaxRoadWidthPx pixels
  };

  /**
   * The image's texture in grey levels: the median standard deviation of
   * 7 x 7 px windows on a grid over 9 x 9 patches of the image (fields,
   * grass and roofs alike; noise included).
   */
  double textureGrey( const GreyTiles &grey );

  //! The widest road extraction looks for, in pixels (wider roads of a large-scale photo are left out).
  constexpr double kMaxRoadWidthPx = 80.0;

  /**
   * Road widths `widthM` (narrowest, widest; metres) in pixels of image
   * `a` at the terrain height `heightM`: divided by the ground pixel at
   * the image's centre, kept within 1 .. kMaxRoadWidthPx. Throws
   * std::invalid_argument for widths that are not 0 < narrowest <= widest,
   * or when the image's centre does not see the ground at that height.
   */
  RoadWidthsPx widthsPxFor( const OrientedImage &a, double heightM, const std::pair<double, double> &widthM );

  //! How the pair was read.
  struct PairReading
  {
    bool inWindows = false;     //!< read a window at a time (else held whole)
    long greyTilesRead = 0;     //!< 256 px tiles of grey levels read, both images
    long matchingWindows = 0;   //!< matching windows prepared
    size_t peakMatchingBytes = 0; //!< the most matching pixel data held at once
  };

  struct RoadNetworkSummary
  {
    std::string mapping;                            //!< "orientation", "projective", "multiquadric"
    std::optional<RegistrationReport> registration; //!< control-point mappings
    double verificationSearchPx = 0.0;              //!< the verification's search either side of the mapped line (verificationSearchPx())
    std::optional<TerrainHeightEstimate> terrainEstimate;
    double meanHeightM = 0.0;
    std::optional<RoadWidthsPx> widthsFromMetres;  //!< when RoadNetworkOptions::roadWidthM set the widths in pixels
    double textureGrey = 0.0;                       //!< the first image's, when the contrast came from it
    double minContrast = 0.0;                       //!< the minimum contrast used (grey levels)
    CoincidentExtractionSummary extraction;
    NetworkIntersectionSummary network;            //!< empty for an unoriented pair
    bool oriented = false;
    PairReading reading;
    double seconds = 0.0;
  };

  /**
   * The verification's search either side of a mapped line for a pair
   * registered by control points: twice the misregistration to expect
   * (RegistrationReport::expectedPx) plus 2 px, within 3 px and
   * `ceilingPx` (VerificationOptions::misregistrationPx); the ceiling where
   * the points cannot tell. A narrow search keeps verification from
   * accepting a parallel line beside the mapped one (a row of buildings, a
   * field's edge), which a real photograph has everywhere.
   */
  double verificationSearchPx( const RegistrationReport &registration, double ceilingPx );

  /**
   * `a` and `b` are the pair's orientations, or both null for an unoriented
   * pair (then `options.control` is required). The images are read a window
   * at a time: grey levels for the extraction through `greyA` / `greyB`,
   * matching pixels for the terrain height and the 3-D lines through
   * `matching` (of the same sizes), so memory does not grow with the images
   * beyond the result matrices (a byte a pixel). Throws
   * std::invalid_argument with one sentence for bad input (sizes, options,
   * control points, no terrain height to be had); read errors propagate; a
   * pair without roads gives an empty result.
   */
  RoadNetworkSummary extractRoadNetwork( const GreyTiles &greyA, const GreyTiles &greyB, PairMatchWindows &matching, const OrientedImage *a,
                                         const OrientedImage *b, const RoadNetworkOptions &options, const Progress &progress = Progress() );

  /**
   * The same for a pair of raster files, read a window at a time through
   * the readers (a 16-bit image's grey range is read first, strip by strip,
   * and its grey levels scaled by it).
   */
  RoadNetworkSummary extractRoadNetwork( std::shared_ptr<const RasterReader> readerA, std::shared_ptr<const RasterReader> readerB, const OrientedImage *a,
                                         const OrientedImage *b, const RoadNetworkOptions &options, const Progress &progress = Progress() );

  //! The same for two images held whole (not windows of them).
  RoadNetworkSummary extractRoadNetwork( const MatchImage &imageA, const MatchImage &imageB, const OrientedImage *a, const OrientedImage *b,
                                         const RoadNetworkOptions &options, const Progress &progress = Progress() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_ROADNETWORKEXTRACTOR_H
