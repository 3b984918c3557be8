"""Tools on top of the library: the command line, the benchmark, the comparison of
analytic and numeric solvers, and the peers they time. The library never imports them."""
