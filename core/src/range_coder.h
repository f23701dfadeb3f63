// ngi core (private): an adaptive binary range coder (the LZMA range coder of Igor Pavlov,
// public domain, as described in "LZMA SDK: lzma.txt", with carry propagation through a
// cached byte), with 16-bit probabilities whose adaptation rate slows as a model sees more
// bits (fast learning on short streams, precise estimates on long ones), and bypass bits.
//
// Safety on hostile input: the decoder never reads outside its span (bytes past the end
// read as 0 and are counted in overrun()); every decode call does a bounded amount of
// work. A caller bounds the number of symbols it decodes and checks overrun() at the end.
//
// Flushing: finish() ends a stream so that a decoder reads exactly its bytes, no more, no
// fewer (consumed() == the stream's size). A coder that flushes, starts a fresh encoder and
// goes on with the same models writes streams that can be concatenated without lengths:
// each decoder finds where its stream ends. A flush costs about 4 bytes (the pending low
// bytes) plus the fractional byte the stream had reached.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace ngi::detail {

// Probability that the next bit is 0, in 1/65536, with a count that sets the rate.
struct BitModel {
    uint16_t p0 = 32768;
    uint8_t seen = 0;

    void update(int bit)
    {
        // Rate 1/2^shift: 1/16 for the first bits, down to 1/128 after ~100.
        const int shift = seen < 8 ? 4 : seen < 24 ? 5 : seen < 96 ? 6 : 7;
        if (seen < 255) ++seen;
        if (bit)
            p0 = uint16_t(p0 - (p0 >> shift));
        else
            p0 = uint16_t(p0 + ((65536 - p0) >> shift));
        p0 = std::clamp<uint16_t>(p0, 64, 65536 - 64);
    }
};

class RangeEncoder {
public:
    void encode(BitModel& m, int bit)
    {
        const uint32_t bound = (range_ >> 16) * m.p0;
        if (bit)
            low_ += bound, range_ -= bound;
        else
            range_ = bound;
        m.update(bit);
        normalize();
    }
    // `count` (<= 24) raw bits of `value`, most significant first, at 1 bit each.
    void encodeBits(uint32_t value, int count)
    {
        for (int i = count - 1; i >= 0; --i) {
            range_ >>= 1;
            if ((value >> i) & 1) low_ += range_;
            normalize();
        }
    }
    // Bytes emitted so far (the stream's size up to the last few pending bytes).
    size_t size() const { return bytes_.size(); }
    // Flushes and returns the stream.
    std::vector<uint8_t> finish()
    {
        for (int i = 0; i < 5; ++i) shiftLow();
        // The first byte LZMA emits is always the initial zero cache: the decoder knows it.
        return std::vector<uint8_t>(bytes_.begin() + std::min<size_t>(1, bytes_.size()), bytes_.end());
    }

private:
    void normalize()
    {
        while (range_ < (1u << 24)) {
            range_ <<= 8;
            shiftLow();
        }
    }
    void shiftLow()
    {
        if (uint32_t(low_) < 0xFF000000u || (low_ >> 32) != 0) {
            const uint8_t carry = uint8_t(low_ >> 32);
            uint8_t temp = cache_;
            do {
                bytes_.push_back(uint8_t(temp + carry));
                temp = 0xFF;
            } while (--cacheSize_ != 0);
            cache_ = uint8_t(low_ >> 24);
        }
        ++cacheSize_;
        low_ = (low_ & 0x00FFFFFFu) << 8;
    }

    uint64_t low_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint8_t cache_ = 0;
    uint64_t cacheSize_ = 1;
    std::vector<uint8_t> bytes_;
};

class RangeDecoder {
public:
    RangeDecoder() = default;  // reads an empty stream; assign a real one before decoding
    explicit RangeDecoder(std::span<const uint8_t> bytes) : bytes_(bytes)
    {
        for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next();
    }
    int decode(BitModel& m)
    {
        const uint32_t bound = (range_ >> 16) * m.p0;
        int bit;
        if (code_ < bound)
            range_ = bound, bit = 0;
        else
            code_ -= bound, range_ -= bound, bit = 1;
        m.update(bit);
        normalize();
        return bit;
    }
    uint32_t decodeBits(int count)
    {
        uint32_t v = 0;
        for (int i = 0; i < count; ++i) {
            range_ >>= 1;
            const uint32_t bit = code_ >= range_ ? 1u : 0u;
            if (bit) code_ -= range_;
            v = (v << 1) | bit;
            normalize();
        }
        return v;
    }
    // Bytes read past the end of the stream (as zeros). The decoder reads exactly the bytes
    // finish() returned, so a complete stream never overruns: overrun() > 0 means truncated.
    size_t overrun() const { return overrun_; }
    // Bytes of the stream not read: a complete stream read to its end leaves none.
    size_t unread() const { return bytes_.size() - at_; }
    // Bytes of the span read so far (after a flushed stream's last symbol: its size).
    size_t consumed() const { return at_; }

private:
    void normalize()
    {
        while (range_ < (1u << 24)) {
            range_ <<= 8;
            code_ = (code_ << 8) | next();
        }
    }
    uint8_t next()
    {
        if (at_ < bytes_.size()) return bytes_[at_++];
        ++overrun_;
        return 0;
    }

    std::span<const uint8_t> bytes_;
    size_t at_ = 0;
    size_t overrun_ = 0;
    uint32_t code_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
};

}  // namespace ngi::detail
