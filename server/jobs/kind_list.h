/* Every job kind, one KIND(id) a line, in the order GET /v1/kinds and the unknown-kind error list
 * them. KIND(id) names the row `const job_kind job_kind_<id>` that jobs/kind_<id>.c defines
 * (its name is the id with '-' for '_'). Adding a kind is one line here (docs/adding-a-kind.md).
 * Included by kinds.h (the rows' declarations) and job_kinds.c (the table): no include guard. */
KIND(optimize)
KIND(family_sweep)
KIND(random_stats)
KIND(table3)
KIND(temporal_optimize)
KIND(compare)
KIND(animation)
KIND(reference_convergence)
KIND(temporal_render)
KIND(sleep)
