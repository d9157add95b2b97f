/***************************************************************************
  resectionalgorithm.h - geostation:resection
  -------------------------------------------------------------------------
  Space resection of one image of a block from control points; writes the
  oriented block and a JSON precision report (docs/conventions.md §8-9).
 ***************************************************************************/
#ifndef RESECTIONALGORITHM_H
#define RESECTIONALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ResectionAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ResectionAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // RESECTIONALGORITHM_H
