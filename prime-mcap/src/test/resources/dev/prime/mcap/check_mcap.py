"""Independent check of an MCAP file with the Python `mcap` package (and `jsonschema`).

Usage: python3 check_mcap.py FILE. Prints one JSON object: per topic the schema, the count
from the summary's Statistics and the count of messages actually read, the first decoded
message; every message validated against its channel's JSON Schema; the data section's and
every chunk's CRC checked by a streaming pass; the summary's CRC recomputed here.
"""
import json
import struct
import sys
import zlib

import jsonschema
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader


def main(path):
    result = {"channels": {}, "schema_errors": [], "log_time_sorted": True}
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        header = reader.get_header()
        result["library"] = header.library
        stats = summary.statistics
        result["message_count"] = stats.message_count
        result["chunk_count"] = stats.chunk_count
        result["chunk_indexes"] = len(summary.chunk_indexes)
        validators = {}
        for channel_id, channel in summary.channels.items():
            schema = summary.schemas[channel.schema_id]
            validators[channel_id] = jsonschema.validators.validator_for(
                json.loads(schema.data))(json.loads(schema.data))
            result["channels"][channel.topic] = {
                "id": channel_id,
                "message_encoding": channel.message_encoding,
                "schema_name": schema.name,
                "schema_encoding": schema.encoding,
                "statistics_count": stats.channel_message_counts.get(channel_id, 0),
                "read_count": 0,
                "first": None,
                # the validator is not vacuous: a list of strings is no record, enum or number
                "rejects_probe": not validators[channel_id].is_valid(["probe"]),
            }
        last_time = -1
        for schema, channel, message in reader.iter_messages(log_time_order=True):
            entry = result["channels"][channel.topic]
            value = json.loads(message.data)
            if entry["read_count"] == 0:
                entry["first"] = value
            entry["read_count"] += 1
            for error in validators[channel.id].iter_errors(value):
                result["schema_errors"].append(
                    "%s #%d: %s" % (channel.topic, message.sequence, error.message))
            if message.log_time < last_time:
                result["log_time_sorted"] = False
            last_time = message.log_time

    with open(path, "rb") as f:
        records = {}
        for record in StreamReader(f, validate_crcs=True).records:
            name = type(record).__name__
            records[name] = records.get(name, 0) + 1
        result["stream_records"] = records
    with open(path, "rb") as f:
        result["streamed_chunks"] = sum(
            1 for record in StreamReader(f, emit_chunks=True).records if type(record).__name__ == "Chunk")

    with open(path, "rb") as f:
        data = f.read()
    footer = len(data) - 8 - 29
    summary_start, summary_offset_start, summary_crc = struct.unpack_from("<QQI", data, footer + 9)
    result["summary_crc_ok"] = zlib.crc32(data[summary_start:footer + 25]) == summary_crc
    result["summary_offset_groups"] = check_summary_offsets(data, summary_offset_start, footer)
    print(json.dumps(result))


def check_summary_offsets(data, start, end):
    """Each SummaryOffset record must span exactly the summary records of its opcode."""
    groups = []
    position = start
    while position < end:
        opcode, length = struct.unpack_from("<BQ", data, position)
        assert opcode == 0x0E, "record %#x in the summary offset section" % opcode
        group_opcode, group_start, group_length = struct.unpack_from("<BQQ", data, position + 9)
        cursor = group_start
        while cursor < group_start + group_length:
            record_opcode, record_length = struct.unpack_from("<BQ", data, cursor)
            assert record_opcode == group_opcode, "group %#x holds a %#x record" % (group_opcode, record_opcode)
            cursor += 9 + record_length
        assert cursor == group_start + group_length, "group %#x ends inside a record" % group_opcode
        groups.append(group_opcode)
        position += 9 + length
    return groups


if __name__ == "__main__":
    main(sys.argv[1])
