/* aalab help [COMMAND] */
#include "commands.h"

#include <string.h>

static const char OVERVIEW[] =
    "usage: aalab [--socket PATH] [--json|--csv] [--timeout S] COMMAND [ARGS]\n"
    "\n"
    "Client of aalabd, the antialiasing-pattern lab daemon.\n"
    "\n"
    "commands:\n"
    "  eval NAME|FILE.json   E2 of a preset or a pattern file (checked locally first)\n"
    "  presets [NAME]        the classic patterns, or one of them\n"
    "  optimize ...          submit an optimization job (--wait to follow it, -q: id only)\n"
    "  submit SPEC.json|-    submit a job of any kind from its JSON spec (--wait, -q)\n"
    "  jobs                  list jobs (--state S, --kind K, --limit N)\n"
    "  job ID                one job: state, its kind's result table, best pattern (--trace)\n"
    "  wait ID               follow a job to its end with a progress bar, then show it\n"
    "  cancel ID             ask a queued or running job to stop (owner or root)\n"
    "  render ...            render a test tile to a PNG\n"
    "  export ID             the best pattern of a job (json, utk, vulkan, d3d12)\n"
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
    "A pattern argument is a preset NAME, a FILE.json, or job:ID (a job's best pattern).\n"
    "\n"
    "exit codes: 0 ok, 1 usage or invalid local file, 2 server answered 4xx,\n"
    "            3 server answered 5xx, 4 cannot connect, 5 job failed/cancelled (--wait, wait)\n";

static const struct {
    const char *command;
    const char *text;
} DETAILS[] = {
    {"eval", "usage: aalab eval NAME|FILE.json [--filter NAME[:B=..,C=..]|JSON]\n"
             "                  [--acuity naiman|naiman-envelope|uniform|FILE.json|JSON] [--angles "
             "A,B,...]\n"
             "                  [--detail]\n"
             "FILE.json holds a pattern ({\"kernels\":...}, {\"mirrored\":...}, {\"tile\":...})\n"
             "or a whole evaluate request ({\"pattern\":P, ...}); options override its fields.\n"
             "--detail adds the per-kernel, per-angle table (angle_deg, weight, e1, weighted).\n"},
    {"presets", "usage: aalab presets [NAME]\n"},
    {"optimize", "usage: aalab optimize --family 'P(4,1+,2)' | --pattern NAME|FILE.json\n"
                 "                      [--seeds N] [--max-seconds S] [--max-iterations N]\n"
                 "                      [--rng-seed K] [--mode weights|positions|both]\n"
                 "                      [--method auto|laine-aila|minimax|smooth]\n"
                 "                      [--executor local|slurm]\n"
                 "                      [--wait] [--poll S] [-q]\n"
                 "Prints the job id. With --wait, follows the job with a progress bar on\n"
                 "stderr, prints the finished job and exits 5 if it failed or was cancelled.\n"
                 "-q prints the bare id (ID=$(aalab optimize -q ...)); with --wait it then\n"
                 "waits silently and the exit code says how the job ended.\n"
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
    {"job", "usage: aalab job ID [--trace] [--csv]\n"
            "The job's state, its kind's result (optimize: E2 and a row per seed;\n"
            "family-sweep: the configurations ranked by E2; random-stats: min, avg, max,\n"
            "Opt W, Opt W+P as in Laine & Aila's Table 3; table3: that table over\n"
            "seeds, mean with a ± column (sd) beside the paper's row; compare, animation,\n"
            "reference-convergence: their tables), the best pattern (x, y and weight of\n"
            "each sample, kernels numbered from 0) and a summary of the trace.\n"
            "--trace: the best E2 against run time (seconds, iterations, evaluations).\n"
            "--csv: the kind's main table (or the trace) as CSV.\n"},
    {"wait", "usage: aalab wait ID [--poll S] [--trace] [--csv]\n"
             "Follows a queued or running job (a progress bar on stderr when it is a\n"
             "terminal), then prints it as 'aalab job' does. Exit 0 if it ended done,\n"
             "5 if it failed, was cancelled or interrupted; Ctrl-C stops waiting, not the job.\n"},
    {"cancel", "usage: aalab cancel ID\n"
               "Asks the job to stop; it ends 'cancelled' at its next check ('aalab wait ID').\n"},
    {"render", "usage: aalab render --pattern NAME|FILE.json [--scene siemens-star]\n"
               "                    [--size 256x256] [--image pattern|reference|difference]\n"
               "                    -o tile.png\n"
               "Prints the render statistics; -o - writes the PNG to stdout (stats to stderr).\n"},
    {"export", "usage: aalab export ID [--format json|utk|vulkan|d3d12] [-o FILE]\n"},
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
