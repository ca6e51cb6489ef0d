// Published best E2 values, drawn on the Families plot as reference marks. Data with its
// provenance: where each number is printed. All use Laine & Aila's metric (Mitchell-Netravali
// (1/3, 1/3) reference, Naiman acuity), which this daemon's default filter and acuity table
// reproduce (data/README.md). The Aalto pattern page (www.tml.tkk.fi/~samuli/patterns, Laine &
// Aila Fig. 11) is not reachable from here, so its values are not included; Fig. 10's curves
// are printed only as a figure.

const LA = 'Laine & Aila 2006, "A Weighted Error Metric and Optimization Method for Antialiasing Patterns"';

export const PUBLISHED_BESTS = [
  { family: 'P(1,1,4)', cost: 4, e2: 0.359, source: `${LA}, Table 2, "Best E2" (2×2 uniform grid and rotated grid rows)` },
  { family: 'P(1,1+,2)', cost: 2, e2: 0.359, source: `${LA}, Table 2, "Best E2" (Quincunx row), as printed` },
  { family: 'P(4,1+,2)', cost: 2, e2: 0.359, source: `${LA}, Table 2, "Best E2" (Flipquad row)` },
  { family: 'P(4,1+,1.25)', cost: 1.25, e2: 0.56, source: `${LA}, Table 2, "Best E2" (Fliptri row)` },
  { family: 'P(16,16,4)', cost: 4, e2: 0.161, source: `${LA}, Table 3, Opt W+P from the best of 1000 Poisson-disk patterns` },
  { family: 'P(16,16,4)', cost: 4, e2: 0.169, source: `${LA}, Table 3, Opt W+P from the best of 1000 jittered-grid patterns` },
];
