/***************************************************************************
  revisionmerge.h - the revisions of one map by overlapping pairs, as one
  -------------------------------------------------------------------------
  A strip or block of pairs revises one map pair by pair (maprevision.h):
  where pairs overlap, a map road is revised by each of them, and where a
  pair does not see a road it says `outside`. Merged, each map road is
  cut at every place where some pair's piece begins or ends (its place
  along the map road, RevisedPiece::fromM / toM), and each stretch takes
  the status of the pair that tells most about it:

    confirmed > moved > not_found > occluded > outside

  (a pair that sees the road on its course outweighs one that sees it
  elsewhere or not at all; one that sees the place outweighs one whose
  view is blocked or that does not cover it), ties going to the higher
  evidence and then to the pair first by name. Consecutive stretches of
  one status are one piece again, its course the chosen pieces' courses
  cut at the stretch's ends (vertices placed along the map road by
  RevisedPiece::alongMapM; σ carried with them), its evidence and shift
  their means weighted by length, and it names the pairs it came from.
  Pairs are taken in the order of their names and roads in the order of
  their ids, so the result does not depend on the order of the inputs.
 ***************************************************************************/
#ifndef GEOSTATION_REVISION_REVISIONMERGE_H
#define GEOSTATION_REVISION_REVISIONMERGE_H

#include <string>
#include <vector>

#include "revision/maprevision.h"

namespace geostation
{

  //! One pair's revision: its pieces, `road` being the map feature's id (the same in every pair).
  struct PairRevision
  {
    std::string pair;
    std::vector<RevisedPiece> pieces;
  };

  struct MergedRevisionPiece
  {
    RevisedPiece piece;              //!< road, status, evidence, shift, course (+ sigma, stereo, alongMapM), fromM, toM
    std::vector<std::string> pairs;  //!< the pairs whose pieces it is made of, in the order of their names
    size_t pairIndex = 0;            //!< the pair (index into the input) whose piece gave its first stretch
    size_t pieceIndex = 0;           //!< and that piece (index into its pieces): the feature's attributes
  };

  struct RevisionMergeSummary
  {
    std::vector<MergedRevisionPiece> pieces; //!< roads in the order of their ids, each along its course
    int piecesIn = 0;
    double seenTwiceM = 0.0;    //!< map length seen (not outside) by more than one pair
    double disagreedM = 0.0;    //!< of that, where the pairs' statuses differ among confirmed, moved and not_found
    //! Total length along the map roads of the pieces with `status` (m).
    double lengthM( RevisionStatus status ) const;
  };

  /**
   * The pairs' revisions as one (see the file comment). Throws
   * std::invalid_argument with one sentence for two pairs of one name, or a
   * piece whose places along the map road do not match its course
   * (alongMapM of another size than course, or fromM > toM).
   */
  RevisionMergeSummary mergeRevisions( const std::vector<PairRevision> &pairs );

  //! The order of trust: 0 confirmed, 1 moved, 2 not_found, 3 occluded, 4 outside, 5 invalid_geometry.
  int revisionRank( RevisionStatus status );

} // namespace geostation

#endif // GEOSTATION_REVISION_REVISIONMERGE_H
