/***************************************************************************
  photoidentification.cpp - control identified in a photo file, end to end
 ***************************************************************************/
#include "identification/photoidentification.h"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include <Eigen/LU>

namespace geostation
{

  void PhotoIdentificationOptions::check() const
  {
    marks.check();
    identification.check();
    if ( !( agreementPx > 0.0 ) )
      throw std::invalid_argument( "The agreement of the two passes must be a positive number of pixels." );
  }

  PhotoIdentificationSummary identifyControlInPhoto( const cv::Mat &greyFile, const Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile,
      const std::vector<ControlPoint> &control, const PhotoIdentificationOptions &options )
  {
    options.check();
    Eigen::Matrix<double, 2, 3> toNominal;
    toNominal << 1, 0, 0, 0, 1, 0;
    if ( nominalFromFile )
      toNominal = *nominalFromFile;
    const Eigen::Matrix2d linear = toNominal.leftCols<2>();
    if ( std::abs( linear.determinant() ) < 1e-12 )
      throw std::invalid_argument( "The scan affine of the photo is singular." );
    auto fileOf = [&]( const Eigen::Vector2d &nominal ) { return Eigen::Vector2d( linear.inverse() * ( nominal - toNominal.col( 2 ) ) ); };

    // the marks, in the camera's nominal frame (a tenth of the work), then the search
    PhotoIdentificationSummary summary;
    if ( !options.identification.progress.report( 0.0, "the marks" ) )
    {
      summary.identification.status = ControlIdentificationSummary::Status::Cancelled;
      summary.identification.message = "the identification was cancelled";
      return summary;
    }
    const std::vector<MarkCandidate> found = detectMarkCandidates( greyFile, options.marks );
    std::vector<Eigen::Vector2d> candidates;
    for ( const MarkCandidate &m : found )
      candidates.push_back( toNominal * m.pixelInImage.homogeneous() );
    summary.candidates = static_cast<int>( candidates.size() );
    ControlIdentificationOptions search = options.identification;
    search.progress = options.identification.progress.part( 0.1, 0.95 );
    summary.identification = identifyControl( camera, control, candidates, search );
    if ( !summary.identification.ok() )
      return summary;

    // the second pass: every control point located again at its prediction from the identified orientation, at its
    // predicted size; what it finds consistent with the rest is measured there, a control point the distance lists
    // missed included (a mark the candidates did not hold, too large or too small for them)
    ControlPredictionOptions completion;
    completion.marks = options.marks;
    const ControlPredictionSummary completed = predictAndFindControl( nominalFromFile ? nominalImage( greyFile, camera, toNominal ) : greyFile, camera,
        summary.identification.resection.exterior, control, {}, completion );
    std::map<std::string, const PredictedPoint *> second;
    if ( completed.ok() )
      for ( const PredictedPoint &p : completed.points )
        second[p.pointId] = &p;
    const auto foundAgain = [&]( const std::string &id ) -> const PredictedPoint * {
      const auto it = second.find( id );
      return it != second.end() && it->second->status == PredictedPoint::Status::Found ? it->second : nullptr;
    };
    // a mark is claimed within agreementPx of its prediction, and within three times the marks' median residual
    // (at least 0.5 px): where the others lie within 0.05 px of theirs, one 0.7 px off is not the mark's centre
    std::vector<double> residuals;
    for ( const auto &[id, p] : second )
      if ( p->status == PredictedPoint::Status::Found )
        residuals.push_back( ( p->pixelInImage - p->predictedPx ).norm() );
    std::sort( residuals.begin(), residuals.end() );
    const double claimLimitPx = residuals.size() >= 3 ? std::min( options.agreementPx, std::max( 0.5, 3.0 * residuals[residuals.size() / 2] ) ) : options.agreementPx;
    summary.claimLimitPx = claimLimitPx;
    std::set<std::string> claimed;
    for ( const IdentifiedControl &id : summary.identification.identified )
    {
      PhotoIdentifiedPoint point;
      point.pointId = id.pointId;
      const PredictedPoint *again = foundAgain( id.pointId );
      point.relocated = again != nullptr;
      const Eigen::Vector2d nominal = again ? again->pixelInImage : id.pixelInImage;
      const Eigen::Vector2d predicted = again || second.count( id.pointId ) ? second.at( id.pointId )->predictedPx : Eigen::Vector2d( id.pixelInImage + id.residualPx );
      point.pixelInFile = again ? fileOf( nominal ) : found[id.candidate].pixelInImage;
      point.sigmaPx = again ? completion.sigmaPx : options.identification.candidateSigmaPx;
      point.predictedInFile = fileOf( predicted );
      claimed.insert( id.pointId );
      // the final orientation is good to a fraction of a pixel: a mark further off is not claimed
      if ( completed.ok() && ( nominal - predicted ).norm() > claimLimitPx )
      {
        summary.flagged.push_back( point );
        ++summary.unclaimed;
        continue;
      }
      summary.relocated += point.relocated ? 1 : 0;
      summary.identified.push_back( point );
    }
    for ( const ControlPoint &c : control )
      if ( const PredictedPoint *again = foundAgain( c.id ); again && !claimed.count( c.id ) )
      {
        PhotoIdentifiedPoint point;
        point.pointId = c.id;
        point.relocated = true;
        point.pixelInFile = fileOf( again->pixelInImage );
        point.predictedInFile = fileOf( again->predictedPx );
        point.sigmaPx = completion.sigmaPx;
        claimed.insert( c.id );
        if ( ( again->pixelInImage - again->predictedPx ).norm() > claimLimitPx )
        {
          summary.flagged.push_back( point );
          ++summary.unclaimed;
          continue;
        }
        summary.identified.push_back( point );
        ++summary.relocated;
        ++summary.addedAtPrediction;
      }
    for ( const PredictedControl &p : summary.identification.notFound )
      if ( !claimed.count( p.pointId ) )
        summary.notFound.emplace_back( p.pointId, fileOf( p.pixelInImage ) );
    return summary;
  }

} // namespace geostation
