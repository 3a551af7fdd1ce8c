#include "gl/handles.h"
#include "gl/resources.h"

#include <doctest/doctest.h>

#include <type_traits>

using namespace rtgi::gl;

TEST_CASE("RAII handles are move-only and start empty") {
    static_assert(!std::is_copy_constructible_v<TextureHandle>);
    static_assert(!std::is_copy_assignable_v<TextureHandle>);
    static_assert(std::is_nothrow_move_constructible_v<BufferHandle>);
    static_assert(!std::is_copy_constructible_v<Texture>);
    static_assert(!std::is_copy_constructible_v<Buffer>);
    static_assert(!std::is_copy_constructible_v<LedgerEntry>);
    TextureHandle t;
    CHECK(t.id() == 0u);
    CHECK_FALSE(bool(t));
    TextureHandle moved(std::move(t));
    CHECK(moved.id() == 0u);
}

TEST_CASE("memory ledger entries follow their owner") {
    MemoryLedger ledger;
    {
        LedgerEntry a(&ledger, "a", 100);
        LedgerEntry b(&ledger, "b", 20);
        CHECK(ledger.total() == 120);
        LedgerEntry c(std::move(a));
        CHECK(ledger.total() == 120);
        c = LedgerEntry();
        CHECK(ledger.total() == 20);
        CHECK(ledger.entries().count("a") == 0);
    }
    CHECK(ledger.total() == 0);
    CHECK(groupCount(1, 8) == 1u);
    CHECK(groupCount(8, 8) == 1u);
    CHECK(groupCount(9, 8) == 2u);
    CHECK(bytesPerTexel(GL_RGBA16F) == 8);
    CHECK(bytesPerTexel(GL_R32F) == 4);
}
