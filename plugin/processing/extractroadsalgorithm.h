/***************************************************************************
  extractroadsalgorithm.h - geostation:extract_roads
 ***************************************************************************/
#ifndef EXTRACTROADSALGORITHM_H
#define EXTRACTROADSALGORITHM_H

#include <qgsprocessingalgorithm.h>

#include "geostation_processing_export.h"

class GEOSTATION_PROCESSING_EXPORT ExtractRoadsAlgorithm : public QgsProcessingAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString shortHelpString() const override;
    ExtractRoadsAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

#endif // EXTRACTROADSALGORITHM_H
