/***************************************************************************
  rigroles.h - which image of a station plays a given part in the rig
  -------------------------------------------------------------------------
  A road line is followed in the "reference" image of every station and
  found in its stereo "partner". Which image that is at the next station is
  decided by geometry, not by the camera entry: a block whose images share
  one camera model (COLMAP's single_camera, a rig of identical cameras)
  has two images of the same camera at every station. An image's part in
  the rig is its pose relative to the station's other images: where they
  lie in its camera frame and how they are turned against it. At the next
  station the image whose relations match best takes the part, its camera
  entry and the turn of its axis since the last station breaking ties.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_RIGROLES_H
#define GEOSTATION_TRACING_RIGROLES_H

#include <vector>

#include <Eigen/Core>

#include "io/block.h"
#include "io/stationsequence.h"

namespace geostation
{
  //! Where another image of the station lies, seen from one image: its projection centre in the image's camera frame and its rotation against it.
  struct RigRelation
  {
    Eigen::Vector3d offset = Eigen::Vector3d::Zero(); //!< R (C_other - C), m
    Eigen::Matrix3d turn = Eigen::Matrix3d::Identity(); //!< R_other R^T: the other camera's frame from this one's
  };

  //! How `other` lies as seen from `image` (both oriented).
  RigRelation rigRelation( const BlockImage &image, const BlockImage &other );

  /**
   * How far two relations differ: the offsets' difference over the longer
   * offset (at least 0.1 m), plus the angle between the turns over 10 deg.
   * Below about 0.5 for the same pair of cameras of a rig oriented at two
   * stations; 2 for a left and a right camera swapped.
   */
  double rigRelationCost( const RigRelation &a, const RigRelation &b );

  /**
   * The image that plays `seed`'s part at each station of the sequence
   * (nullptr where none does), chained from the seed's station
   * (`seedStation`, an index into the sequence) outward, each station
   * compared with the nearest one before it that had the part (and with
   * the relations of the fullest station of the part so far).
   */
  std::vector<const BlockImage *> imagesInRole( const Block &block, const StationSequence &sequence, int seedStation, const BlockImage &seed );

  /**
   * The oriented image of `station`, other than `reference`, that lies as
   * `relation` says as seen from it (the seed pair's relation); nullptr if
   * none is within a cost of 1 (rigRelationCost). An image of
   * `preferredCameraId` wins a near tie.
   */
  const BlockImage *imageInRelation( const Block &block, const SequenceStation &station, const BlockImage &reference, const RigRelation &relation,
                                     const std::string &preferredCameraId );

  /**
   * The seed station's stereo partner: the oriented image of `station`,
   * other than `reference`, that sees the ground point at least 20 px
   * inside its frame, its optical axis closest to the reference's; nullptr
   * if none does.
   */
  const BlockImage *stereoPartnerSeeing( const Block &block, const SequenceStation &station, const BlockImage &reference, const Eigen::Vector3d &ground );

} // namespace geostation

#endif // GEOSTATION_TRACING_RIGROLES_H
