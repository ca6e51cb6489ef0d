/* aalab help [COMMAND] */
#include "commands.h"

#include <string.h>

static const char OVERVIEW[] =
    "usage: aalab [--socket PATH] [--json|--csv] [--timeout S] COMMAND [ARGS]\n"
    "\n"
    "Client of aalabd, the antialiasing-pattern lab daemon.\n"
    "\n"
    "commands:\n"
    "  eval NAME|FILE.json   E2 of a preset or a pattern file (checked locally first);\n"
    "                        --temporal PRESET: a TAA jitter sequence, per phase\n"
    "  presets [NAME]        the classic patterns, or one of them\n"
    "  optimize ...          submit an optimization job (--wait to follow it, -q: id only)\n"
    "  submit SPEC.json|-    submit a job of any kind from its JSON spec (--wait, -q)\n"
    "  jobs                  list jobs (--state S, --kind K, --limit N)\n"
    "  job ID                one job: state, its kind's result table, best pattern (--trace)\n"
    "  wait ID               follow a job to its end with a progress bar, then show it\n"
    "  cancel ID             ask a queued or running job to stop (owner or root)\n"
    "  render ...            render a test tile to a PNG\n"
    "  predict ...           predicted RMSE of patterns on a scene, without rendering\n"
    "  analyze NAME|FILE     discrepancies, spacing and spectrum of a pattern's tile\n"
    "  export ID             the best pattern of a job (json, utk, xyw, csv, points-json,\n"
    "                        vulkan, d3d12)\n"
    "  convert PATTERN       a preset, pattern or point-set file in another format\n"
    "  health                daemon version, uptime, workers, queue\n"
    "  filters               reference filters the metric accepts\n"
    "  acuity                acuity tables (angle weights)\n"
    "  enumerate ...         configurations of a family and cost\n"
    "  token ...             a token for the dashboard (TCP); token list, token revoke ID\n"
    "  help [COMMAND]        this text, or a command's options\n"
    "\n"
    "global options:\n"
    "  -s, --socket PATH     daemon socket (default: $AALAB_SOCKET, else\n"
    "                        $XDG_RUNTIME_DIR/aalab/aalabd.sock if it exists,\n"
    "                        else /run/aalab/aalabd.sock)\n"
    "      --json            print the daemon's JSON instead of tables\n"
    "      --csv             print tables as CSV (RFC 4180, header row), e.g. for pandas\n"
    "      --timeout S       per-request timeout in seconds (default 30)\n"
    "  -V, --version         print the client's version\n"
    "\n"
    "A pattern argument is a preset NAME, a FILE.json, job:ID (a job's best pattern), or a\n"
    "point-set file: .dat (UTK, x y), .txt or .xyw (x y [w]), .csv (header x,y[,w]), .json\n"
    "array of points, .bin (UTK binary), .rps (PSA float32), points in [0,1) of the whole\n"
    "tile; --points-format utk|xyw|csv|json|bin|rps for other names, --set N for one set of\n"
    "a file holding several, --tile T (default 1), --kernel K (default 1) and --weights\n"
    "file|filter|equal (default file: a w per point) say how to read them ('aalab help\n"
    "convert'). Files exported by aalab carry a '# aalab-pattern' line that restores the\n"
    "exact pattern.\n"
    "\n"
    "exit codes: 0 ok, 1 usage or invalid local file, 2 server answered 4xx,\n"
    "            3 server answered 5xx, 4 cannot connect, 5 job failed/cancelled (--wait, wait)\n";

static const struct {
    const char *command;
    const char *text;
} DETAILS[] = {
    {"eval", "usage: aalab eval NAME|FILE.json|POINTS [--filter NAME[:B=..,C=..]|JSON]\n"
             "                  [--acuity naiman|naiman-envelope|uniform|FILE.json|JSON]\n"
             "                  [--angles A,B,...] [--detail] [--points-format F] [--tile T]\n"
             "                  [--kernel K] [--weights file|filter|equal]\n"
             "FILE.json holds a pattern ({\"kernels\":...}, {\"mirrored\":...}, {\"tile\":...})\n"
             "or a whole evaluate request ({\"pattern\":P, ...}); options override its fields.\n"
             "--detail adds the per-kernel, per-angle table (angle_deg, weight, e1, weighted).\n"
             "POINTS is a point-set file ('aalab help convert'); --weights filter weighs its\n"
             "samples by --filter.\n"
             "\n"
             "usage: aalab eval --temporal PRESET|FILE.json|JSON|GENERATOR [--alpha A]\n"
             "                  [--blend box|exponential|A] [--cut-frames K]\n"
             "                  [--resolve FILTER[:K=V,..]] [--frame-pattern NAME|FILE]\n"
             "A TAA jitter sequence under a blend (docs/temporal.md): a temporal preset\n"
             "(halton23-8, halton23-16, fsr2-1.5x .. fsr2-3x, urp-like, filament-rgss4,\n"
             "filament-halton8/16/32), a {\"temporal\":...} file or object, or a generator:\n"
             "halton:N[:START], r2:N[:START], rgss4, fsr2:SCALE, positions:PRESET. A FILE.json\n"
             "holding {\"temporal\":...} may also be given as the pattern argument. Prints\n"
             "E2 of the worst phase, the mean over phases, F2 (flicker), frames to 5 %, the\n"
             "per-phase table (newest offset, E2, argmax angle) and the E2 after k frames\n"
             "since a cut; --detail adds per angle E1 (worst, mean) and F1; --csv: the\n"
             "per-phase table (with --detail the per-angle one); --json: the whole answer.\n"
             "  aalab eval --temporal halton23-8 --alpha 0.05\n"
             "  aalab eval --temporal positions:d3d-4x --blend box\n"},
    {"presets", "usage: aalab presets [NAME]\n"},
    {"analyze", "usage: aalab analyze NAME|FILE.json|POINTS [--metrics LIST] [--radius R]\n"
                "                     [--pcf-bins N] [--points-format F] [--tile T] [--csv]\n"
                "                     [--set N|all]\n"
                "Point-set analysis of the pattern's tile on the unit torus (docs/analysis.md):\n"
                "the L2 discrepancies CD, WD, MD, L2-star (root, square in brackets), the exact\n"
                "Linf star discrepancy, spacing against PSA's packing distance, the spectrum's\n"
                "effective Nyquist frequency and oscillation, then the radial spectrum.\n"
                "--metrics picks from discrepancy,star_discrepancy,spacing,spectrum,pcf;\n"
                "--radius: the periodogram's largest frequency (1..128, default 32);\n"
                "--csv: the radial spectrum as CSV; --json: the daemon's whole answer (with the\n"
                "2-D periodogram and the pair correlation function).\n"
                "--set all: every set of a file holding several ('#'-separated text, UTK .bin),\n"
                "the figures averaged (the spectrum of the mean periodogram, as pbrt's pspec).\n"},
    {"optimize", "usage: aalab optimize --family 'P(4,1+,2)' | --pattern NAME|FILE.json|POINTS\n"
                 "                      [--seeds N] [--max-seconds S] [--max-iterations N]\n"
                 "                      [--rng-seed K] [--mode weights|positions|both]\n"
                 "                      [--method auto|laine-aila|minimax|smooth]\n"
                 "                      [--executor local|slurm]\n"
                 "                      [--scene S [--size WxH] [--angle DEG] [--blend A]]\n"
                 "                      [--wait] [--poll S] [-q]\n"
                 "                      [--points-format F] [--tile T] [--kernel K]\n"
                 "                      [--weights file|filter|equal]\n"
                 "Prints the job id. With --wait, follows the job with a progress bar on\n"
                 "stderr, prints the finished job and exits 5 if it failed or was cancelled.\n"
                 "-q prints the bare id (ID=$(aalab optimize -q ...)); with --wait it then\n"
                 "waits silently and the exit code says how the job ended.\n"
                 "--scene optimises for a scene (its edge-model RMSE, docs/predict.md), blended\n"
                 "with E2 by --blend A in [0, 1] (default 0: the scene alone); the result\n"
                 "prints the predicted RMSE and E2 beside the global-E2 optimum's.\n"
                 "--method picks the step rule (default auto: minimax for --mode weights,\n"
                 "smooth for P(4,4,n) and P(16,16,n), laine-aila otherwise).\n"
                 "--max-iterations N without --max-seconds: a budget of N steps per seed and\n"
                 "no clock, so the result depends on the spec and --rng-seed only.\n"
                 "--executor slurm runs the seeds as a Slurm job array (docs/cluster.md).\n"},
    {"submit", "usage: aalab submit SPEC.json|- [--wait] [--poll S] [-q]\n"
               "SPEC is the POST /v1/jobs body, e.g. {\"kind\":\"family-sweep\",...}; the\n"
               "kinds, their fields and runnable examples are at GET /v1/kinds.\n"
               "With --wait: progress bar on stderr, exit 5 if the job fails or is cancelled.\n"
               "-q prints the bare id, for ID=$(aalab submit -q spec.json).\n"},
    {"jobs", "usage: aalab jobs [--state queued|running|done|failed|cancelled|interrupted]\n"
             "                  [--kind KIND] [--limit N] [--csv]\n"
             "Newest first: id, kind, state, progress, family, label, best E2, owner, created.\n"},
    {"job", "usage: aalab job ID [--trace] [--pattern] [--csv]\n"
            "The job's state, its kind's result (optimize: E2 and a row per seed;\n"
            "family-sweep: the configurations ranked by E2; random-stats: min, avg, max,\n"
            "Opt W, Opt W+P as in Laine & Aila's Table 3; table3: that table over\n"
            "seeds, mean with a ± column (sd) beside the paper's row; with a spec's\n"
            "metrics, both add Spearman's rho of each point-set figure with E2; compare,\n"
            "animation, reference-convergence: their tables), a line on the best pattern\n"
            "(family, cost, E2, kernels) and a summary of the trace; a failed job's error\n"
            "first.\n"
            "--pattern: the best pattern in full (x, y and weight of each sample, kernels\n"
            "numbered from 0).\n"
            "--trace: the best E2 against run time (seconds, iterations, evaluations).\n"
            "--csv: the kind's main table (or the trace) as CSV.\n"},
    {"wait", "usage: aalab wait ID [--poll S] [--trace] [--pattern] [--csv]\n"
             "Follows a queued or running job (a progress bar on stderr when it is a\n"
             "terminal), then prints it as 'aalab job' does. Exit 0 if it ended done,\n"
             "5 if it failed, was cancelled or interrupted; Ctrl-C stops waiting, not the job.\n"},
    {"cancel", "usage: aalab cancel ID\n"
               "Asks the job to stop; it ends 'cancelled' at its next check ('aalab wait ID').\n"},
    {"render", "usage: aalab render --pattern NAME|FILE.json|POINTS [--scene siemens-star]\n"
               "                    [--size 256x256] [--image pattern|reference|difference]\n"
               "                    -o tile.png\n"
               "Prints the render statistics; -o - writes the PNG to stdout (stats to stderr).\n"},
    {"predict", "usage: aalab predict --pattern NAME|FILE[,NAME|FILE...] [--scene siemens-star]\n"
                "                     [--size 256x256] [--angle DEG] [--csv]\n"
                "                     [--model edge|reference-profile|exact]\n"
                "The edge model's RMSE (0..255) of each pattern on the scene, as a render would\n"
                "measure it, from the scene's edge lengths per angle and the patterns' E1\n"
                "(docs/predict.md). Pixel-locked edges are exact; detail below the pixel scale\n"
                "is not predicted (its image share is printed). --model reference-profile\n"
                "measures E1 against the render's own reference across each angle; exact adds\n"
                "exact sums over straight edges' pixels (half-planes near 27 and 63 degrees).\n"},
    {"export", "usage: aalab export ID [--format json|utk|xyw|csv|bin|rps|points-json|vulkan|\n"
               "                    d3d12|metal] [-o FILE]\n"
               "The best pattern of a job: json, aalab's pattern JSON (the default); utk, xyw,\n"
               "csv, bin, points-json, point sets in [0,1) of the whole tile that read back as\n"
               "the same pattern ('aalab help convert'); rps, PSA's float32 points alone;\n"
               "vulkan, d3d12, metal, programmable sample positions where the API can express\n"
               "the pattern.\n"},
    {"convert", "usage: aalab convert NAME|FILE.json|POINTS|job:ID\n"
                "                     [--format json|utk|xyw|csv|bin|rps|points-json|vulkan|\n"
                "                     d3d12|metal] [-o FILE] [--points-format F] [--tile T]\n"
                "                     [--kernel K] [--weights file|filter|equal] [--set N]\n"
                "Writes a pattern in another format (default json) with the daemon's own\n"
                "writer, locally (job:ID asks the daemon). Point sets have one convention:\n"
                "points in [0,1) of the whole tile, x right, y along the tile's y axis:\n"
                "  utk   .dat: 'x y' per line, '#' comments\n"
                "  xyw   .txt, .xyw: 'x y' or 'x y w' per line\n"
                "  csv   .csv: a header line naming x, y and optionally w\n"
                "  json  .json: [[x,y],...], [[x,y,w],...] or {\"x\":..,\"y\":..,\"w\":..}\n"
                "  bin   .bin: UTK's binary file (float32/64, 2-D), the aalab line as a trailer\n"
                "  rps   .rps: PSA's raw float32 x y pairs, no header (give --tile, --weights)\n"
                "utk and xyw files may hold several sets separated by '#' lines (UTK, pbrt's\n"
                "pspec; concatenated exports too): --set N reads set N (from 0).\n"
                "Reading one: --tile T scales the points to a T x T pixel tile (default 1),\n"
                "--kernel K as in the tile form; --weights file takes each point's w (kernel 1),\n"
                "filter weighs each kernel's samples by the reference filter, equal by 1/n.\n"
                "aalab's exports start with '# aalab-pattern {...}' (json: {\"aalab\":...}),\n"
                "which restores the exported pattern exactly; other tools skip it.\n"
                "e.g. aalab convert flipquad --format csv -o flipquad.csv\n"
                "     aalab eval points.dat --tile 2 --weights filter\n"},
    {"health", "usage: aalab health\n"},
    {"filters", "usage: aalab filters\n"},
    {"acuity", "usage: aalab acuity\n"},
    {"enumerate", "usage: aalab enumerate --family 'P(4,1+,n)' --cost 1.25\n"
                  "       aalab enumerate --family 'P(4,1+,1.25)'\n"},
    {"token", "usage: aalab token [--label TEXT]\n"
              "       aalab token list\n"
              "       aalab token revoke ID\n"
              "Issues a bearer token for the daemon's TCP listener (the dashboard), acting as\n"
              "you; it is shown once, with the dashboard URL when the daemon has a listener.\n"
              "'list' shows your tokens (root: all), 'revoke' ends one at once.\n"},
    {"help", "usage: aalab help [COMMAND]\n"},
    {"version", "usage: aalab version\n"},
};

void cmd_help(FILE *out, const char *command)
{
    if (command)
        for (size_t i = 0; i < sizeof DETAILS / sizeof DETAILS[0]; i++)
            if (strcmp(DETAILS[i].command, command) == 0) {
                fputs(DETAILS[i].text, out);
                return;
            }
    fputs(OVERVIEW, out);
}
