// Validation of viewer messages against @foxglove/schemas' JSON schemas (ajv), and of
// plugslam.Status against the schema the host advertises for it.
"use strict";
const { skip } = require("./lib");

function validators() {
  let Ajv, schemas;
  try {
    Ajv = require("ajv");
    schemas = require("@foxglove/schemas/jsonschema");
  } catch (e) {
    skip(`npm packages missing (${e.message.split("\n")[0]}): run scripts/install-web-deps.sh`);
  }
  // The schemas use annotations (contentEncoding, $comment) that strict mode would refuse.
  const ajv = new Ajv({ strict: false, allErrors: true });
  const compiled = new Map();
  return (schemaName, advertisedSchema) => {
    if (compiled.has(schemaName)) return compiled.get(schemaName);
    let schema;
    if (schemaName.startsWith("foxglove.")) {
      schema = schemas[schemaName.slice("foxglove.".length)];
      if (!schema) throw new Error(`@foxglove/schemas has no ${schemaName}`);
    } else {
      schema = JSON.parse(advertisedSchema);
    }
    const validate = ajv.compile(schema);
    const check = (message) => (validate(message) ? null : ajv.errorsText(validate.errors));
    compiled.set(schemaName, check);
    return check;
  };
}

module.exports = { validators };
