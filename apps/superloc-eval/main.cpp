// superloc-eval: ATE, RPE, robustness (Rp, Rr), map outlier %, timing of one run (doc/evaluation.md).
#include <superloc/core/errors.h>
#include <superloc/app/eval_app.h>

#include <iostream>

int main(int argc, char** argv) {
    try {
        superloc::app::EvalApp app;
        app.initialize(std::vector<std::string>(argv + 1, argv + argc));
        return app.run(std::cout);
    } catch (const std::exception& e) {
        std::cerr << "superloc-eval: " << superloc::oneLineError(e) << "\n";
        return 1;
    }
}
