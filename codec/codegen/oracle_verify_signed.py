#!/usr/bin/env python3
"""The oracle's verdict on IEEE 1609.2 data and certificates that the project's code wrote
(issue 13, part 5: "we sign -> the oracle verifies").

Input (stdin), one JSON object a line:
    {"name", "kind": "data" | "certificate", "coer": hex,
     "signer": hex of the signer's certificate (data), or of the issuer's (certificate);
               absent for a self-signed root}
Output (stdout), one line per input: "<name> ok" or "<name> fail <why>".

Independence: decoding and re-encoding by pycrate's IEEE 1609.2 module (COER), the hash
rule, ECDSA verification and the compressed-y parity check by Python `cryptography` and the
textbook affine arithmetic of make_signed_vectors.py (beside this script); nothing here
calls the project's Rust code. The to-be-signed bytes are pycrate's re-encoding of what it
decoded, so a non-canonical encoding fails too.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_signed_vectors as m  # noqa: E402  (the vector generator's helpers)


def key_of(cert_coer):
    """The explicit verification key of a certificate (COER), via pycrate."""
    m.CERT.from_coer(cert_coer)
    tbs = m.CERT.get_val()['toBeSigned']
    kind, key = tbs['verifyKeyIndicator']
    if kind != 'verificationKey' or key[0] != 'ecdsaNistP256':
        raise ValueError('not an explicit P-256 key: %s' % kind)
    return m.public_from_point(key[1])


def verdict(item):
    raw = bytes.fromhex(item['coer'])
    signer = bytes.fromhex(item['signer']) if item.get('signer') else None
    if item['kind'] == 'data':
        m.DATA.from_coer(raw)
        if m.DATA.to_coer() != raw:
            return 'fail non-canonical encoding'
        kind, sd = m.DATA.get_val()['content']
        if kind != 'signedData':
            return 'fail not signed data'
        tbs = m.coer(m.TBS_DATA, sd['tbsData'])
        pub = key_of(signer)
        return 'ok' if m.verify(pub, tbs, signer, sd['signature']) else 'fail signature'
    m.CERT.from_coer(raw)
    if m.CERT.to_coer() != raw:
        return 'fail non-canonical encoding'
    val = m.CERT.get_val()
    tbs = m.coer(m.TBS_CERT, val['toBeSigned'])
    pub = key_of(signer) if signer else key_of(raw)
    return 'ok' if m.verify(pub, tbs, signer, val['signature']) else 'fail signature'


def main():
    for line in sys.stdin:
        if not line.strip():
            continue
        item = json.loads(line)
        try:
            result = verdict(item)
        except Exception as e:  # a decode error is the oracle's refusal, reported as such
            result = 'fail %s: %s' % (type(e).__name__, e)
        print(item['name'], result, flush=True)


if __name__ == '__main__':
    main()
