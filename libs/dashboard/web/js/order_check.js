// The checks the server makes on an order (openapi.yaml OrderRequest), made before sending it so
// people see at once what is wrong: a box type of the catalog, at least one candy, each candy of
// the catalog and once only, each quantity a whole number of 1 or more, all together at most the
// box's capacity.

// lines: [{candy, quantity}] as entered (quantity a text or number). Returns {request, errors}:
// the request body {box, candy: {name: n}} when there are no errors.
export function checkOrder(catalog, box, lines) {
  const errors = [];
  const boxType = (catalog.box_types || []).find((b) => b.name === box);
  if (!boxType) errors.push('choose a box type');
  const known = new Set((catalog.candy_types || []).map((c) => c.name));
  const candy = {};
  for (const line of lines) {
    const quantity = Number(line.quantity);
    if (!line.candy) {
      errors.push('choose a candy type for every line');
    } else if (!known.has(line.candy)) {
      errors.push(`${line.candy} is not a candy of the catalog`);
    } else if (line.candy in candy) {
      errors.push(`${line.candy} is in more than one line`);
    } else if (!Number.isInteger(quantity) || quantity < 1) {
      errors.push(`the quantity of ${line.candy} must be a whole number of 1 or more`);
    } else {
      candy[line.candy] = quantity;
    }
  }
  if (lines.length === 0) errors.push('add at least one candy');
  const total = Object.values(candy).reduce((a, b) => a + b, 0);
  if (boxType && total > boxType.capacity) {
    errors.push(`${total} candies do not fit in a ${boxType.name} (${boxType.capacity} at most)`);
  }
  return errors.length ? {request: null, errors, total} : {request: {box, candy}, errors, total};
}
