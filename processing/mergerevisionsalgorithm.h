/***************************************************************************
  mergerevisionsalgorithm.h - geostation:merge_revisions
  -------------------------------------------------------------------------
  The revisions that revise_roads made of one map with overlapping pairs,
  made one (core/revision/revisionmerge.h): each map road once, each
  stretch with the status of the pair that tells most about it, its
  measured course and sigma from that pair. What geostation-batch revise
  runs after its units.
 ***************************************************************************/
#ifndef MERGEREVISIONSALGORITHM_H
#define MERGEREVISIONSALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT MergeRevisionsAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    MergeRevisionsAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // MERGEREVISIONSALGORITHM_H
