/***************************************************************************
  photoidentification.cpp - control identified in a photo file, end to end
 ***************************************************************************/
#include "identification/photoidentification.h"

#include <map>
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

    // the marks, in the camera's nominal frame
    const std::vector<MarkCandidate> found = detectMarkCandidates( greyFile, options.marks );
    std::vector<Eigen::Vector2d> candidates;
    for ( const MarkCandidate &m : found )
      candidates.push_back( toNominal * m.pixelInImage.homogeneous() );
    PhotoIdentificationSummary summary;
    summary.candidates = static_cast<int>( candidates.size() );
    summary.identification = identifyControl( camera, control, candidates, options.identification );
    if ( !summary.identification.ok() )
      return summary;

    // the second pass: every mark located again at its prediction from the identified orientation
    ControlPredictionOptions completion;
    completion.marks = options.marks;
    const ControlPredictionSummary completed = predictAndFindControl( nominalFromFile ? nominalImage( greyFile, camera, toNominal ) : greyFile, camera,
        summary.identification.resection.exterior, control, {}, completion );
    std::map<std::string, Eigen::Vector2d> relocated;
    for ( const PredictedPoint &p : completed.points )
      if ( completed.ok() && p.status == PredictedPoint::Status::Found )
        relocated[p.pointId] = p.pixelInImage;
    for ( const IdentifiedControl &id : summary.identification.identified )
    {
      PhotoIdentifiedPoint point;
      point.pointId = id.pointId;
      const auto r = relocated.find( id.pointId );
      point.relocated = r != relocated.end() && ( r->second - id.pixelInImage ).norm() <= options.agreementPx;
      point.pixelInFile = point.relocated ? fileOf( r->second ) : found[id.candidate].pixelInImage;
      point.sigmaPx = point.relocated ? completion.sigmaPx : options.identification.candidateSigmaPx;
      point.predictedInFile = fileOf( id.pixelInImage + id.residualPx );
      summary.relocated += point.relocated ? 1 : 0;
      summary.identified.push_back( point );
    }
    for ( const PredictedControl &p : summary.identification.notFound )
      summary.notFound.emplace_back( p.pointId, fileOf( p.pixelInImage ) );
    return summary;
  }

} // namespace geostation
