/***************************************************************************
  geostationplugin.h - the GeoStation plugin for QGIS desktop
  -------------------------------------------------------------------------
  Thin: the menu, the toolbar and their actions. Everything photogrammetric
  is done by core; the Processing provider is registered here too so the
  toolbox has the algorithms even without the Python bridge.
 ***************************************************************************/
#ifndef GEOSTATIONPLUGIN_H
#define GEOSTATIONPLUGIN_H

#include <memory>

#include <QObject>
#include <QPointer>

#include <qgisplugin.h>

class QAction;
class QMenu;
class QToolBar;
class QgisInterface;

namespace geostation
{
  class Block;
}

class GeoStationPlugin : public QObject, public QgisPlugin
{
    Q_OBJECT

  public:
    explicit GeoStationPlugin( QgisInterface *iface );
    ~GeoStationPlugin() override;

    void initGui() override;
    void unload() override;

    //! The block opened last, or nullptr.
    const geostation::Block *block() const { return mBlock.get(); }

  public slots:
    /**
     * Opens a block file. Any problem is shown in the message bar as one
     * sentence naming the file and the JSON path; the previously opened block
     * stays open. Returns true on success.
     */
    bool openBlockFile( const QString &path );

    //! Asks for a block file and opens it.
    void openBlock();

    //! Shows the cameras, stations and images of the open block.
    void showBlockInfo();

    //! Opens the Processing dialog of an algorithm (e.g. "geostation:resection").
    void showAlgorithmDialog( const QString &algorithmId );

  signals:
    void blockOpened( const QString &path );

  private:
    QAction *addAction( const QString &objectName, const QString &icon, const QString &text, const QString &tip, void ( GeoStationPlugin::*slot )() );
    //! A menu action (in `menu`) that opens a Processing algorithm's dialog.
    QAction *addAlgorithmAction( QMenu *menu, const QString &objectName, const QString &text, const QString &algorithmId );
    QString blockSummary( const geostation::Block &block ) const;
    void updateActions();

    QgisInterface *mIface = nullptr;
    QPointer<QMenu> mMenu;
    QPointer<QMenu> mAdjustmentMenu;
    QPointer<QToolBar> mToolBar;
    QList<QAction *> mActions;
    QAction *mBlockInfoAction = nullptr;
    bool mRegisteredProvider = false;
    std::unique_ptr<geostation::Block> mBlock;
};

#endif // GEOSTATIONPLUGIN_H
