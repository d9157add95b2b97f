/***************************************************************************
  rigroles.cpp - which image of a station plays a given part (rigroles.h)
 ***************************************************************************/
#include "tracing/rigroles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace geostation
{
  namespace
  {
    constexpr double kPi = 3.14159265358979323846;
    constexpr double kDegree = kPi / 180.0;
    //! an image's relations to more than this cost from the part's are another part (rigRelationCost)
    constexpr double kMaxRoleCost = 1.0;
    //! a camera entry other than the part's counts as this much cost: it decides only between near-equal poses
    constexpr double kOtherCameraCost = 0.3;
    //! the turn of the axis from the last station's image over this angle counts as a cost of 1
    constexpr double kAxisTurnScale = 30.0 * kDegree;
    //! the seed station's partner must see the line this far inside its frame
    constexpr double kPartnerMarginPx = 20.0;

    double angleBetween( const Eigen::Matrix3d &a, const Eigen::Matrix3d &b )
    {
      const double c = std::clamp( ( ( a.transpose() * b ).trace() - 1.0 ) / 2.0, -1.0, 1.0 );
      return std::acos( c );
    }

    //! The relations of `image` to the station's other oriented images.
    std::vector<RigRelation> relationsOf( const Block &block, const SequenceStation &station, const BlockImage &image )
    {
      std::vector<RigRelation> out;
      for ( const std::string &id : station.imageIds )
        if ( const BlockImage *other = block.findImage( id ); other && other->id != image.id && other->exterior )
          out.push_back( rigRelation( image, *other ) );
      return out;
    }

    /**
     * How far a candidate's relations are from the part's: each relation of
     * the shorter list matched to its nearest in the other, averaged (a
     * station with a camera missing still matches on the others). Where
     * either image is alone in its station there is nothing to compare: 1.
     */
    double relationsCost( const std::vector<RigRelation> &candidate, const std::vector<RigRelation> &part )
    {
      if ( candidate.empty() && part.empty() )
        return 0.0;
      if ( candidate.empty() || part.empty() )
        return kMaxRoleCost;
      const std::vector<RigRelation> &few = candidate.size() <= part.size() ? candidate : part;
      const std::vector<RigRelation> &many = candidate.size() <= part.size() ? part : candidate;
      double sum = 0.0;
      for ( const RigRelation &r : few )
      {
        double best = std::numeric_limits<double>::infinity();
        for ( const RigRelation &s : many )
          best = std::min( best, rigRelationCost( r, s ) );
        sum += best;
      }
      return sum / few.size();
    }

    //! The image of `station` that plays the part `previous` played at its station (relations `part`); nullptr if none.
    const BlockImage *bestInRole( const Block &block, const SequenceStation &station, const BlockImage &previous, const std::vector<RigRelation> &part )
    {
      const Eigen::Vector3d axis = previous.exterior->viewingDirection();
      const BlockImage *best = nullptr;
      double bestCost = std::numeric_limits<double>::infinity();
      for ( const std::string &id : station.imageIds )
      {
        const BlockImage *image = block.findImage( id );
        if ( !image || !image->exterior )
          continue;
        const double relations = relationsCost( relationsOf( block, station, *image ), part );
        if ( relations > kMaxRoleCost )
          continue;
        const double turn = std::acos( std::clamp( axis.dot( image->exterior->viewingDirection() ), -1.0, 1.0 ) );
        const double cost = relations + turn / kAxisTurnScale + ( image->cameraId == previous.cameraId ? 0.0 : kOtherCameraCost );
        if ( cost < bestCost )
        {
          bestCost = cost;
          best = image;
        }
      }
      return best;
    }
  } // namespace

  RigRelation rigRelation( const BlockImage &image, const BlockImage &other )
  {
    const Eigen::Matrix3d cameraFromWorld = image.exterior->worldFromCamera().transpose();
    RigRelation r;
    r.offset = cameraFromWorld * ( other.exterior->projectionCentre - image.exterior->projectionCentre );
    r.turn = other.exterior->worldFromCamera().transpose() * image.exterior->worldFromCamera();
    return r;
  }

  double rigRelationCost( const RigRelation &a, const RigRelation &b )
  {
    const double scale = std::max( { a.offset.norm(), b.offset.norm(), 0.1 } );
    return ( a.offset - b.offset ).norm() / scale + angleBetween( a.turn, b.turn ) / ( 10.0 * kDegree );
  }

  std::vector<const BlockImage *> imagesInRole( const Block &block, const StationSequence &sequence, int seedStation, const BlockImage &seed )
  {
    std::vector<const BlockImage *> out( sequence.size(), nullptr );
    if ( seedStation < 0 || seedStation >= sequence.size() || !seed.exterior )
      return out;
    out[seedStation] = &seed;
    for ( const int step : { 1, -1 } )
    {
      const BlockImage *previous = &seed;
      std::vector<RigRelation> part = relationsOf( block, sequence.at( seedStation ), seed );
      for ( int k = seedStation + step; k >= 0 && k < sequence.size(); k += step )
      {
        const SequenceStation &station = sequence.at( k );
        out[k] = bestInRole( block, station, *previous, part );
        if ( !out[k] )
          continue;
        previous = out[k];
        // a station with a camera missing says less of the part than the one before it
        if ( std::vector<RigRelation> relations = relationsOf( block, station, *out[k] ); relations.size() >= part.size() )
          part = std::move( relations );
      }
    }
    return out;
  }

  const BlockImage *imageInRelation( const Block &block, const SequenceStation &station, const BlockImage &reference, const RigRelation &relation,
                                     const std::string &preferredCameraId )
  {
    if ( !reference.exterior )
      return nullptr;
    const BlockImage *best = nullptr;
    double bestCost = std::numeric_limits<double>::infinity();
    for ( const std::string &id : station.imageIds )
    {
      const BlockImage *image = block.findImage( id );
      if ( !image || image->id == reference.id || !image->exterior )
        continue;
      const double relationCost = rigRelationCost( rigRelation( reference, *image ), relation );
      if ( relationCost > kMaxRoleCost )
        continue;
      const double cost = relationCost + ( image->cameraId == preferredCameraId ? 0.0 : kOtherCameraCost );
      if ( cost < bestCost )
      {
        bestCost = cost;
        best = image;
      }
    }
    return best;
  }

  const BlockImage *stereoPartnerSeeing( const Block &block, const SequenceStation &station, const BlockImage &reference, const Eigen::Vector3d &ground )
  {
    if ( !reference.exterior )
      return nullptr;
    const BlockImage *best = nullptr;
    double bestCos = -2.0;
    const Eigen::Vector3d axis = block.orientedImage( reference ).cameraFromWorldRotation().row( 2 ).transpose();
    for ( const std::string &id : station.imageIds )
    {
      const BlockImage *image = block.findImage( id );
      if ( !image || image->id == reference.id || !image->exterior )
        continue;
      const OrientedImage candidate = block.orientedImage( *image );
      const GroundProjection p = candidate.projectGroundToPixel( ground );
      const Camera &camera = candidate.camera();
      if ( !p.ok() || p.pixelInImage.x() < kPartnerMarginPx || p.pixelInImage.y() < kPartnerMarginPx || p.pixelInImage.x() > camera.width - kPartnerMarginPx ||
           p.pixelInImage.y() > camera.height - kPartnerMarginPx )
        continue;
      const double c = axis.dot( candidate.cameraFromWorldRotation().row( 2 ).transpose() );
      if ( c > bestCos )
      {
        bestCos = c;
        best = image;
      }
    }
    return best;
  }

} // namespace geostation
