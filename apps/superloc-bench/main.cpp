// superloc-bench: a suite of sequences x methods -> results.md / results.json / plots (doc/evaluation.md).
#include <superloc/core/errors.h>
#include <superloc/app/bench_app.h>
#include <superloc/app/eval_app.h>
#include <superloc/app/process.h>
#include <superloc_build_version.h>

#include <iostream>

int main(int argc, char** argv) {
    try {
        superloc::app::killChildOnTermination();
        superloc::app::BenchApp app;
        app.data_dir = SUPERLOC_DEFAULT_DATA;
        app.version = SUPERLOC_BUILD_VERSION;
        app.initialize(std::vector<std::string>(argv + 1, argv + argc));
        return app.run(std::cout, std::cerr);
    } catch (const std::exception& e) {
        std::cerr << "superloc-bench: " << superloc::oneLineError(e) << "\n";
        return 1;
    }
}
