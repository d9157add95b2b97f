/***************************************************************************
  networkmerge.h - the road networks of overlapping pairs made one
  -------------------------------------------------------------------------
  A block's stereo pairs overlap: a road in the overlap is extracted by two
  pairs, and a road crossing a pair's border ends there in one pair and
  starts in the next. Merging makes one network of them:
    - a stretch of a line that runs along a line already merged (within the
      tolerance, about parallel; a sample or two off its direction, where
      the line wavers, do not break it) is a duplicate: it is dropped and
      its pair is added to the line it repeats;
    - what is left of it is a piece of its own; a piece that leaves the end
      of a merged line in its direction continues that line (a border
      joined), one that leaves its side ends on it (a junction, the node
      shared by both lines);
    - crossing roads are never duplicates of each other, and a pair's own
      lines are never compared with each other (its extraction already made
      them one per road).
  The pairs are taken in the order of their names and each pair's lines in
  their order, so the result does not depend on the order in which the
  pairs were extracted.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_NETWORKMERGE_H
#define GEOSTATION_EXTRACTION_NETWORKMERGE_H

#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! One extracted line of a pair's network, as its OUTPUT holds it.
  struct PairNetworkLine
  {
    std::vector<Eigen::Vector3d> points; //!< block CRS, metres
    double sigmaM = 0.0;                 //!< its largest vertex sigma
  };

  //! A pair's network: its name (e.g. "S0001-S0002") and its lines.
  struct PairNetwork
  {
    std::string pair;
    std::vector<PairNetworkLine> lines;
  };

  struct NetworkMergeOptions
  {
    double toleranceM = 0.0;    //!< two lines closer than this are one road; 0: 3 x the larger sigma of the two, at least minToleranceM
    double minToleranceM = 1.0; //!< the tolerance's floor (a road's centre is not found closer than this by two pairs)
    double parallelDeg = 30.0;  //!< a duplicate runs within this angle of the line it repeats; an end continues a line within it
    double sampleM = 1.0;       //!< lines are compared at points this far apart (XY)
    double minPieceM = 0.0;     //!< a piece left over shorter than this is dropped; 0: 2 x the tolerance

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct MergedNetworkLine
  {
    std::vector<Eigen::Vector3d> points;
    double sigmaM = 0.0;
    std::vector<std::string> pairs; //!< the pairs that found it, by name
    double lengthM() const;         //!< XY
  };

  struct NetworkMergeSummary
  {
    std::vector<MergedNetworkLine> lines;
    int linesIn = 0;
    double lengthInM = 0.0;        //!< of all pairs' lines (XY)
    double duplicateLengthM = 0.0; //!< dropped as repeating a merged line
    int bordersJoined = 0;         //!< pieces that continue a merged line
    int junctions = 0;             //!< pieces ending on the side of a merged line
  };

  /**
   * The networks of `pairs` as one (see the file comment). Throws
   * std::invalid_argument for bad options or two pairs of one name.
   */
  NetworkMergeSummary mergeNetworks( const std::vector<PairNetwork> &pairs, const NetworkMergeOptions &options = NetworkMergeOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_NETWORKMERGE_H
