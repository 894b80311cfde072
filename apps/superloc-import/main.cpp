// superloc-import: converts a folder of scans or a ROS 1 / ROS 2 bag into a rawlog. See
// superloc::app::ImportApp (modules/app).
#include <superloc/app/command_line.h>
#include <superloc/app/import_app.h>
#include <superloc/core/errors.h>

#include <iostream>

int main(int argc, char** argv) {
    try {
        return superloc::app::ImportApp::run(superloc::app::argList(argc, argv));
    } catch (const std::exception& e) {
        std::cerr << "superloc-import: " << superloc::oneLineError(e) << std::endl;
        return 1;
    }
}
