// What Foxglove's and Lichtblick's JSON Schema reader accepts (Lichtblick, packages/mcap-support/src/
// parseJsonSchema.ts; a channel whose schema it refuses shows nothing, only an alert): an object with
// "properties"; each property one "type" of boolean, string, number, integer, object or array (or a "oneOf"
// of numeric consts); an array's "items" one of boolean, string (no contentEncoding), number, integer or
// object. No "$ref", no type list, no array of arrays. Returns the reasons a schema breaks this ([] if none).
"use strict";

const FIELD = new Set(["boolean", "string", "number", "integer", "object", "array"]);
const ITEM = new Set(["boolean", "string", "number", "integer", "object"]);

function viewerProblems(schema, path = "") {
  if (schema.type !== "object") return [`${path || "root"}: type ${JSON.stringify(schema.type)}, not "object"`];
  const problems = [];
  for (const [name, field] of Object.entries(schema.properties || {})) {
    const at = path ? `${path}.${name}` : name;
    if (Array.isArray(field.oneOf) && field.oneOf.every((a) => typeof a.const === "number")) continue;
    if (!FIELD.has(field.type)) {
      problems.push(`${at}: type ${JSON.stringify(field.type)}${field.$ref ? " ($ref)" : ""}`);
    } else if (field.type === "object") {
      problems.push(...viewerProblems(field, at));
    } else if (field.type === "array") {
      const item = field.items || {};
      if (!ITEM.has(item.type)) problems.push(`${at}[]: item type ${JSON.stringify(item.type)}`);
      else if (item.type === "string" && item.contentEncoding !== undefined) problems.push(`${at}[]: encoded strings`);
      else if (item.type === "object") problems.push(...viewerProblems(item, `${at}[]`));
    }
  }
  return problems;
}

module.exports = { viewerProblems };
