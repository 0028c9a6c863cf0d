// node-mavlink, a MAVLink implementation that shares nothing with pensight's, on the other end
// of pensight's frames (tests/mavlink/node_mavlink_test.cpp).
//   node node_mavlink.js decode FRAMES OUT  a line per frame: "msgid seq sysid compid name=value ..."
//                                           (every field of the message), then "invalid=N unknown=N"
//   node node_mavlink.js encode LINES OUT   a v2 frame per line of that form (fields not named: 0)
'use strict';
const fs = require('fs');
const {MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common} =
    require('node-mavlink');

const REGISTRY = {...minimal.REGISTRY, ...common.REGISTRY};
const [mode, input, output] = process.argv.slice(2);

if (mode === 'decode') {
  const splitter = new MavLinkPacketSplitter();
  const lines = [];
  splitter.pipe(new MavLinkPacketParser())
      .on('data', (packet) => {
        const h = packet.header;
        const clazz = REGISTRY[h.msgid];
        const data = packet.protocol.data(packet.payload, clazz);
        const fields = clazz.FIELDS.map((f) => `${f.source}=${data[f.name]}`);
        lines.push([h.msgid, h.seq, h.sysid, h.compid, ...fields].join(' '));
      })
      .on('end', () => {
        lines.push(`invalid=${splitter.invalidPackages} unknown=${splitter.unknownPackagesCount}`);
        fs.writeFileSync(output, lines.join('\n') + '\n');
      });
  splitter.end(fs.readFileSync(input));
} else if (mode === 'encode') {
  const frames = fs.readFileSync(input, 'utf8').trim().split('\n').map((line) => {
    const [msgid, seq, sysid, compid, ...fields] = line.split(' ');
    const clazz = REGISTRY[msgid];
    const message = new clazz();
    for (const field of fields) {
      const [name, value] = field.split('=');
      message[clazz.FIELDS.find((f) => f.source === name).name] = Number(value);
    }
    return new MavLinkProtocolV2(Number(sysid), Number(compid)).serialize(message, Number(seq));
  });
  fs.writeFileSync(output, Buffer.concat(frames));
} else {
  console.error('usage: node node_mavlink.js decode|encode IN OUT');
  process.exit(2);
}
