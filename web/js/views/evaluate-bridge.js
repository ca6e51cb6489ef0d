// Lets other views read the pattern currently shown in Evaluate without importing its module
// state directly.
let getter = () => null;
export function setEvaluatePatternGetter(fn) {
  getter = fn;
}
export function currentEvaluatePattern() {
  return getter();
}
