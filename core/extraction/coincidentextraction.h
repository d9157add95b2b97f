/***************************************************************************
  coincidentextraction.h - lines extracted in a stereo pair, each verified
  in the partner (report §3, §4.4, §4.5)
  -------------------------------------------------------------------------
  Round 1 extracts in image A (starting points, LEM, REM), compiles the
  new lines into maximum-length polygons (erasing them), maps them into B
  and verifies them there: accepted parts enter B's result matrix as E
  and A's as I. Round 2 extracts in B from the verification dead ends and
  from B's own starting points, and verifies in A; round 3 continues in A
  from its verification dead ends only; and so on, alternating, until a
  round adds less than a fraction of what has been accepted (or the round
  limit). Final processing joins open ends that face each other across a
  stretch the image supports (a road in shadow), bridges small gaps and
  broken intersections from every open end (the kite-shaped search of
  §4.4.3, 20 x 12 matrix elements there, scaled here with the widest road),
  prunes spurs, and compiles the final polygons of both images from the
  symbols I and E.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_COINCIDENTEXTRACTION_H
#define GEOSTATION_EXTRACTION_COINCIDENTEXTRACTION_H

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "extraction/companionlines.h"
#include "extraction/lineextractor.h"
#include "extraction/pairmapping.h"
#include "extraction/roadborders.h"
#include "extraction/verification.h"

namespace geostation
{

  struct CoincidentExtractionOptions
  {
    LineExtractionOptions extraction;
    VerificationOptions verification;
    int maxRounds = 4;
    double minRoundGain = 0.02;   //!< stop after a round whose accepted length is below this fraction of the total
    double kiteLengthPx = 0.0;    //!< the intersection search's main axis (§4.4.3: 20); 0: twice the widest road, at least 20 px
    double kiteWidthPx = 0.0;     //!< and its smaller axis (12); 0: the widest road, at least 12 px
    bool verify = true;           //!< false: one extraction in A, nothing verified (for comparison)
    RoadBorderOptions borders;       //!< a final line along a road's border (shoulder, kerb) moved onto the road
    CompanionLineOptions companions; //!< markings, kerbs and shoulders along a road, removed from the final lines
    double minBandSupport = 0.5;  //!< a final line goes where its band support (bandSupport(), verification.h; beyond the mouths of its junctions) is below this (0: none goes; roads up to 4 px wide: none)
    double maxBandWidening = 1.6; //!< and where its band widens steadily by this factor or more from one end to the other (bandSupport()'s widening; 0: none goes for it)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct RoundReport
  {
    int round = 0;
    std::string image;            //!< "A" or "B": where this round extracted
    int startingPoints = 0, linesStarted = 0, continued = 0;
    int polygons = 0, wholly = 0, partly = 0, rejected = 0;
    double extractedPx = 0.0, acceptedPx = 0.0;
    double seconds = 0.0;
  };

  struct CoincidentExtractionSummary
  {
    std::vector<CompiledPolygon> linesA, linesB;       //!< final maximum-length polygons (pixelInImage of each image), moved onto their band's centre (centrerefinement.h)
    std::vector<Eigen::Vector2d> intersectionsA, intersectionsB;
    std::vector<DeadEnd> deadEndsA, deadEndsB;         //!< open ends of the final network
    std::vector<RoundReport> rounds;
    StageCounts startStage, lemStage, remStage, verificationStage, compilationStage;
    int bridged = 0;                                   //!< gaps and intersections closed by the final processing
    int pruned = 0;                                    //!< spurs removed by the final processing
    int companionsRemoved = 0;                         //!< lines beside a wider one (markings, kerbs, shoulders), both images
    int bordersMoved = 0;                              //!< final lines moved from a road's border onto the road, both images
    int unsupportedRemoved = 0;                        //!< lines whose band support was below CoincidentExtractionOptions::minBandSupport or whose band widened by maxBandWidening, both images
    int subImages = 0;                                 //!< sub-images processed, all rounds and runs
    int temporaryDeadEnds = 0;                         //!< lines continued across sub-image borders
    bool cancelled = false;
  };

  /**
   * Runs the coincident procedure on images A and B, read a window at a
   * time (only the two result matrices, one byte per pixel, are held
   * whole). Throws std::invalid_argument for bad options; reader errors
   * propagate; cancelling returns with `cancelled` and no lines.
   */
  CoincidentExtractionSummary extractCoincident( const GreyTiles &greyA, const GreyTiles &greyB, const PairMapping &mapping,
                                                 const CoincidentExtractionOptions &options, const Progress &progress = Progress() );

  //! The same for images held in memory (CV_8UC1); std::invalid_argument for other images.
  CoincidentExtractionSummary extractCoincident( const cv::Mat &greyA, const cv::Mat &greyB, const PairMapping &mapping,
                                                 const CoincidentExtractionOptions &options, const Progress &progress = Progress() );

  /**
   * Closes gaps from the open ends of the lines of `symbols` in the matrix:
   * the other line's pixel in the kite ahead of each end nearest to its
   * course (distance along it plus three times the distance across) is
   * joined to it with `symbol`. Returns the number of joins.
   */
  int bridgeOpenEnds( ResultMatrix &matrix, const std::string &symbols, uint8_t symbol, double kiteLengthPx, double kiteWidthPx );

  /**
   * Closes long gaps (a stretch of road in shadow, a junction's mouth): two
   * open ends within `maxDistancePx` that face each other (within 25
   * degrees of the line between them) are joined with `symbol` when no line
   * lies between them and the image shows a band of the road's width,
   * followed from one end (its offset from the line between the ends
   * tracked, for a curved road), along at least 70 % of the way (one side
   * may be lost in shadow) or along 55 % with no interruption longer than
   * three road widths (a tree's shadow across the road, a junction's mouth),
   * and arriving within half a road width of the other end (not a strip
   * beside it). The join is drawn along the band's centre. Returns the
   * number of joins.
   */
  int bridgeFacingEnds( ResultMatrix &matrix, const GreyTiles &grey, const std::string &symbols, uint8_t symbol, const LineObjectOptions &object, double maxDistancePx );

  /**
   * Removes spurs: lines of `symbols` shorter than `maxLengthPx` that run from
   * an intersection to a dead end (left by bridging and by lines that wander
   * into a junction). Returns the number removed.
   */
  int pruneSpurs( ResultMatrix &matrix, const std::string &symbols, double maxLengthPx );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_COINCIDENTEXTRACTION_H
