// Published best E2 values, drawn on the Families plot as reference marks. Data with its
// provenance: where each number is printed. All use Laine & Aila's metric (Mitchell-Netravali
// (1/3, 1/3) reference, Naiman acuity), which this daemon's default filter and acuity table
// reproduce (data/README.md). The Aalto pattern page (Laine's "Optimized Antialiasing Patterns",
// users.aalto.fi/~laines9/patterns, formerly www.tml.tkk.fi/~samuli/patterns; E2 recomputed in
// its Sept. 2010 update) lists the best pattern per family and cost; its P(1,1,n), P(4,1+,n) and
// P(1,4,n) tables are below, read from a stored copy of the page (its P(4,4,n) and P(16,16,n)
// tables were not in that copy). Fig. 10's curves are printed only as a figure.

const AALTO = 'Laine, "Optimized Antialiasing Patterns" (users.aalto.fi/~laines9/patterns, Sept. 2010 update)';
const LA = 'Laine & Aila 2006, "A Weighted Error Metric and Optimization Method for Antialiasing Patterns"';

export const PUBLISHED_BESTS = [
  { family: 'P(1,1,4)', cost: 4, e2: 0.359, source: `${LA}, Table 2, "Best E2" (2×2 uniform grid and rotated grid rows)` },
  { family: 'P(1,1+,2)', cost: 2, e2: 0.359, source: `${LA}, Table 2, "Best E2" (Quincunx row), as printed` },
  { family: 'P(4,1+,2)', cost: 2, e2: 0.359, source: `${LA}, Table 2, "Best E2" (Flipquad row)` },
  { family: 'P(4,1+,1.25)', cost: 1.25, e2: 0.56, source: `${LA}, Table 2, "Best E2" (Fliptri row)` },
  { family: 'P(16,16,4)', cost: 4, e2: 0.161, source: `${LA}, Table 3, Opt W+P from the best of 1000 Poisson-disk patterns` },
  { family: 'P(16,16,4)', cost: 4, e2: 0.169, source: `${LA}, Table 3, Opt W+P from the best of 1000 jittered-grid patterns` },
  { family: 'P(1,1,2)', cost: 2, e2: 0.696, source: `${AALTO}, P(1,1,n) table` },
  { family: 'P(1,1,3)', cost: 3, e2: 0.480, source: `${AALTO}, P(1,1,n) table` },
  { family: 'P(1,1,4)', cost: 4, e2: 0.359, source: `${AALTO}, P(1,1,n) table` },
  { family: 'P(1,1,5)', cost: 5, e2: 0.301, source: `${AALTO}, P(1,1,n) table` },
  { family: 'P(1,1,6)', cost: 6, e2: 0.274, source: `${AALTO}, P(1,1,n) table` },
  { family: 'P(4,1+,2)', cost: 2, e2: 0.359, source: `${AALTO}, P(4,1+,n) table` },
  { family: 'P(4,1+,3)', cost: 3, e2: 0.301, source: `${AALTO}, P(4,1+,n) table` },
  { family: 'P(4,1+,4)', cost: 4, e2: 0.274, source: `${AALTO}, P(4,1+,n) table` },
  { family: 'P(4,1+,5)', cost: 5, e2: 0.259, source: `${AALTO}, P(4,1+,n) table` },
  { family: 'P(4,1+,6)', cost: 6, e2: 0.249, source: `${AALTO}, P(4,1+,n) table` },
  { family: 'P(1,4,2)', cost: 2, e2: 0.465, source: `${AALTO}, P(1,4,n) table` },
  { family: 'P(1,4,3)', cost: 3, e2: 0.335, source: `${AALTO}, P(1,4,n) table` },
  { family: 'P(1,4,4)', cost: 4, e2: 0.241, source: `${AALTO}, P(1,4,n) table` },
  { family: 'P(1,4,5)', cost: 5, e2: 0.197, source: `${AALTO}, P(1,4,n) table` },
  { family: 'P(1,4,6)', cost: 6, e2: 0.168, source: `${AALTO}, P(1,4,n) table` },
];
