// Layout checks the screenshot suites share (layout, temporal, analysis).

/* Pairs of text labels of one SVG whose boxes overlap by more than 2 px each way, named by the
 * nearest id (the svg's, its parent's or grandparent's). */
export function overlappingLabels(page) {
  return page.evaluate(() => {
    const out = [];
    for (const svg of document.querySelectorAll('main svg')) {
      if (!svg.getClientRects().length) continue;
      const boxes = [...svg.querySelectorAll('text')]
        .filter((t) => t.textContent.trim() && t.getClientRects().length)
        .map((t) => ({ t: t.textContent.trim(), r: t.getBoundingClientRect() }))
        .filter((b) => b.r.width > 0 && b.r.height > 0);
      const where = svg.id || svg.parentElement.id || (svg.parentElement.parentElement || {}).id;
      for (let i = 0; i < boxes.length; i++)
        for (let j = i + 1; j < boxes.length; j++) {
          const a = boxes[i].r;
          const b = boxes[j].r;
          const ox = Math.min(a.right, b.right) - Math.max(a.left, b.left);
          const oy = Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top);
          if (ox > 2 && oy > 2) out.push(`${where}: "${boxes[i].t}" / "${boxes[j].t}"`);
        }
    }
    return out;
  });
}
