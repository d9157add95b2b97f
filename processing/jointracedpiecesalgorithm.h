/***************************************************************************
  jointracedpiecesalgorithm.h - geostation:join_traced_pieces
  -------------------------------------------------------------------------
  The pieces of long lines traced from several seeds (trace_road_lines
  runs, one per seed) joined into one line per line id, with the places
  where consecutive pieces disagree beyond 3 sigma or do not meet
  (core/tracing/piecejoin.h). What geostation-batch trace runs after its
  units.
 ***************************************************************************/
#ifndef JOINTRACEDPIECESALGORITHM_H
#define JOINTRACEDPIECESALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT JoinTracedPiecesAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    JoinTracedPiecesAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // JOINTRACEDPIECESALGORITHM_H
