//! Every built-in searcher passes the searcher conformance kit.

use trust::SearchKind;
use trust::testing::check_searcher;

#[test]
fn every_builtin_searcher_passes_the_kit() {
    for kind in SearchKind::ALL {
        check_searcher(|| kind.build());
    }
}
